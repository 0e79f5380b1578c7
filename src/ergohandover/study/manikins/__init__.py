"""Study question ``manikins``: the four standard manikins at the headline locations.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
