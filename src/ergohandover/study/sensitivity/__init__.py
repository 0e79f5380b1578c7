"""Study question ``sensitivity``: which modelling choices move the optimum.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
