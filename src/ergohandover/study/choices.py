"""What the study's settings choose among: boundaries, gaze settings and named workers."""

from __future__ import annotations

from ..landscape.grid import BOUNDARY_NAMES
from ..twin.anthropometry import PERCENTILES

BOUNDARIES = BOUNDARY_NAMES
GAZES = ("on", "off")
WORKERS = tuple(sorted(PERCENTILES))
DEFAULT_WORKER = "p50-male"
"""The study's worker (the paper's is a 50th-percentile man), and the population's reference."""
