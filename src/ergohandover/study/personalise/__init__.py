"""Study question ``personalise``: how many handovers to find one worker's optimum.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
