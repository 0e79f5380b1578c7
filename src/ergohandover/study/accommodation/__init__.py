"""Study question ``accommodation``: where REBA and RULA stay low for a workforce.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
