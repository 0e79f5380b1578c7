"""Study question ``capture``: how well each keypoint format measures the twin.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
