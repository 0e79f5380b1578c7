"""Study question ``accommodation``: where REBA and RULA stay low for a workforce.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
