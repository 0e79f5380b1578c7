"""Study question ``people``: the twin beside measured handovers.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
