"""Study question ``personalise``: how many handovers to find one worker's optimum.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
