"""Study question ``baselines``: the optimised location against the shortest-distance one.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
