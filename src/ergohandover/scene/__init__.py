"""The PyBullet scene: the worker, the dual-arm robot and the box; carries and pictures."""
