"""Study question ``robustness``: does the recommendation survive being measured.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
