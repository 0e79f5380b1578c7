"""Study question ``participants``: the VR participant study, simulated with six workers.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
