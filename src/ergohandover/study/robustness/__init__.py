"""Study question ``robustness``: does the recommendation survive being measured.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
