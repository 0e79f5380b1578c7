"""Study question ``validation``: the twin beside published human data.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
