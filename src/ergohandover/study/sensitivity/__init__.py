"""Study question ``sensitivity``: which modelling choices move the optimum.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
