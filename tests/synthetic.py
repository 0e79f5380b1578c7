"""Synthetic landscapes for the environment and agent tests: a 7x7x7 bowl with a unique minimum."""

from __future__ import annotations

import numpy as np

from ergohandover.envs import HandoverEnv, LandscapeScores
from ergohandover.landscape.cache import Landscape, landscape_key, landscape_path
from ergohandover.landscape.grid import Grid
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary

BOWL = Boundary((-0.09, 0.09), (1.00, 1.18), (0.30, 0.48))  # 7 x 7 x 7 cells every 3 cm
CENTRE = (3, 3, 3)
INFEASIBLE = (6, 6, 6)


def bowl_landscape(infeasible=(INFEASIBLE,)) -> Landscape:
    """A 7x7x7 synthetic landscape: score 5 + the rounded distance [cells] to the centre
    (a unique minimum 5 at (3, 3, 3), x = 0), with ``infeasible`` cells flagged."""
    grid = Grid(BOWL, 0.03)
    i, j, k = np.indices(grid.shape).reshape(3, -1)
    score = (5 + np.rint(np.sqrt((i - 3) ** 2 + (j - 3) ** 2 + (k - 3) ** 2))).astype(np.int8)
    flags = np.zeros(grid.size, dtype=np.uint8)
    for cell in infeasible:
        flags[np.ravel_multi_index(cell, grid.shape)] = 4  # "unbalanced"
    arrays = {"flags": flags}
    for name in ("paper_postural", "reba", "reba_ab", "rula"):
        arrays[name] = np.where(flags == 0, score, -1).astype(np.int8)
    return Landscape(grid, "bowl", arrays, {})


def cached_bowl() -> tuple[Evaluator, Grid]:
    """The bowl stored in the landscape cache (the test session's own) as the default
    evaluator's landscape of the bowl's grid, so that the landscape door returns it for
    (evaluator, grid), as it would a swept one."""
    bowl, evaluator = bowl_landscape(), Evaluator()
    key = landscape_key(evaluator, bowl.grid)
    Landscape(bowl.grid, key, bowl.arrays, bowl.meta).save(landscape_path(key))
    return evaluator, bowl.grid


def bowl_env(**kwargs) -> HandoverEnv:
    return HandoverEnv(LandscapeScores(bowl_landscape()), **kwargs)


def flat(cell) -> int:
    return int(np.ravel_multi_index(cell, (7, 7, 7)))
