"""Study question ``population``: one location for everyone, or one per worker.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
