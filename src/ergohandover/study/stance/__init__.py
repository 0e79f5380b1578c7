"""Study question ``stance``: the headline comparison for a worker who may step.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
