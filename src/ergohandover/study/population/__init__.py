"""Study question ``population``: one location for everyone, or one per worker.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
