"""ergohandover: the most ergonomic place for a robot to hand a box to a worker."""

__version__ = "0.1.0"
