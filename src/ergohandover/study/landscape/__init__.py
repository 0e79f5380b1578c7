"""Study question ``landscape``: the exhaustive landscape of the default worker.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
