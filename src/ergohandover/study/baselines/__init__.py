"""Study question ``baselines``: the optimised location against the shortest-distance one.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
