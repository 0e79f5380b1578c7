"""Study question ``manikins``: the four standard manikins at the headline locations.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
