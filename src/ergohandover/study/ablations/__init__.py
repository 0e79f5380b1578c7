"""Study question ``ablations``: the twin's whole-body solver against PyBullet's IK.

Its entry in :mod:`..registry` declares what it needs, what it writes, whether it has a
headline and its time budget."""
