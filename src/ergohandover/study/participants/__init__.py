"""Study question ``participants``: the VR participant study, simulated with six workers.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
