"""Study question ``stance``: the headline comparison for a worker who may step.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
