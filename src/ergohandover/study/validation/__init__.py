"""Study question ``validation``: the twin beside published human data.

Its entry in :mod:`..registry` declares what it needs, writes, answers and may take."""
