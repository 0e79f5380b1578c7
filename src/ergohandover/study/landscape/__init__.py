"""Study question ``landscape``: the exhaustive landscape of the default worker.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
