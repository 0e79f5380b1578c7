"""A landscape as a point cloud: its feasible cells in the world frame, coloured by a score.

A browser draws a few hundred thousand points smoothly, not a 3 mm landscape's millions: the
cloud keeps every k-th cell along each axis, k the smallest that keeps it under
:data:`MAX_POINTS`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from matplotlib import colormaps

from ..frames import worker_to_world, world_to_worker
from ..landscape import Landscape
from ..robustness.posture_error import ErrorModel, expected_scores
from ..robustness.search import coarse_cells, postures_at
from ..twin.evaluate import Evaluator

MAX_POINTS = 150_000
COLOURMAP = "RdYlGn_r"  # green is a low (good) score, red a high one
EXPECTED_DRAWS = 128  # measurements per cell: the robust search's screening count


class Cloud(NamedTuple):
    """Points (N, 3) world frame [m], float32; each one's score (N,); the stride kept."""

    points: np.ndarray
    values: np.ndarray
    stride: int


def landscape_cloud(landscape: Landscape, score: str) -> Cloud:
    """The landscape's feasible cells, every ``stride``-th along each axis, with ``score``."""
    feasible = int(landscape.feasible.sum())
    stride = max(1, int(np.ceil((feasible / MAX_POINTS) ** (1 / 3))))
    cells = coarse_cells(landscape.grid, stride)
    cells = cells[landscape.feasible[cells]]
    points = worker_to_world(landscape.grid.coordinates(cells)).astype(np.float32)
    return Cloud(points, landscape.arrays[score][cells].astype(int), stride)


def expected_cloud(cloud: Cloud, evaluator: Evaluator, sd_deg: float, seed: int = 0) -> Cloud:
    """The cloud's cells with their expected paper score when every measured angle carries
    Gaussian error of ``sd_deg`` (the robustness part's model; every cell measured with the
    same errors, so that neighbours compare fairly)."""
    posture, feasible = postures_at(world_to_worker(cloud.points.astype(float)), evaluator)
    values = expected_scores(posture, ErrorModel(sd_deg), EXPECTED_DRAWS, seed,
                             settings=evaluator.scoring)
    return Cloud(cloud.points[feasible], values[feasible], cloud.stride)


def zone_cloud(cells, column: str, at_least: float) -> Cloud:
    """The accommodation part's grid points (``cells``: results/accommodation/cells.csv) whose
    share ``column`` is at least ``at_least``, in the world frame, with that share."""
    shares = cells[column].to_numpy(float)
    keep = shares >= at_least
    points = worker_to_world(cells[["x", "y", "z"]].to_numpy(float)[keep]).astype(np.float32)
    return Cloud(points, shares[keep], 1)


def share_colours(shares: np.ndarray) -> np.ndarray:
    """(N, 3) uint8 colours of shares 0-1 (viridis, as the study's figure)."""
    return (255 * colormaps["viridis"](np.clip(shares, 0, 1))[:, :3]).astype(np.uint8)


def colours(values: np.ndarray, low: float, high: float) -> np.ndarray:
    """(N, 3) uint8 colours of scores between ``low`` (green) and ``high`` (red)."""
    share = (values - low) / max(high - low, 1e-9)
    return (255 * colormaps[COLOURMAP](np.clip(share, 0, 1))[:, :3]).astype(np.uint8)
