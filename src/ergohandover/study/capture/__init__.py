"""Study question ``capture``: how well each keypoint format measures the twin.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
