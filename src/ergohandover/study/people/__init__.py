"""Study question ``people``: the twin beside measured handovers.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
