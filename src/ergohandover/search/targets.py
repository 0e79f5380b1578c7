"""What counts as having found the optimum: a target of the learning study.

A target is a set of grid cells on one landscape. Agents minimise an objective E there (their
reward is the env's ``1/E² + S``) and succeed at the first evaluation of a target cell:

- goal ``minimum``: every cell at the objective's lowest value (on the default landscape the
  paper's score reaches its minimum on ~5 % of the grid: almost any search finds one);
- goal ``reward``: the cells of highest reward ``1/E² + S``, the paper's full reward, whose
  symmetry term S picks the cells nearest the midline among those at the minimum (the paper's
  own reason for it: ties). These cells are a subset of the minimum, which is checked.

Because every target cell is at the objective's minimum, an agent's run records every target
cell it evaluated (:attr:`~.trace.Record.best_cells`, with the step it was first seen), so
success and evaluations-to-target are read from the run without touching the agents' loops.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..envs.handover_env import HandoverEnv
from ..errors import ConfigError
from ..landscape.stats import most_symmetric
from .record import Record

GOALS = ("minimum", "reward")


@dataclass(frozen=True)
class TargetCells:
    """The cells of a target.

    Attributes:
        score: the objective at the target cells.
        mask: (grid.size,) True at target cells.
        cells: their flat indices.
        fraction: their share of the grid's cells (the paper counts the whole grid: its score-4
            minimum was 0.004 % of the solution space).
        location: the most symmetric target cell (x, y, z) [m].
    """

    score: float
    mask: np.ndarray
    cells: np.ndarray
    fraction: float
    location: tuple[float, float, float]


def target_cells(env: HandoverEnv, values: np.ndarray, goal: str) -> TargetCells:
    """The target cells of ``goal`` on ``env``'s grid.

    Args:
        env: the env the agents search (its reward defines the ``reward`` goal).
        values: (grid.size,) the objective at every cell, ``inf`` where infeasible.
        goal: one of :data:`GOALS`.
    """
    if goal not in GOALS:
        raise ConfigError(f"goal = {goal!r} is not allowed (use {' or '.join(GOALS)})")
    values = np.asarray(values, dtype=np.float64)
    if not np.isfinite(values).any():
        raise ConfigError("the landscape has no feasible cell: no target")
    lowest = float(values.min())
    mask = values == lowest
    if goal == "reward":
        rewards = env.rewards_of(values)
        mask = rewards == rewards.max()
        if not (values[mask] == lowest).all():
            raise ConfigError("the highest reward is not at the objective's minimum: the "
                              "reward goal needs a run's record of every cell at its best score")
    cells = np.flatnonzero(mask)
    points = env.grid.coordinates(cells)
    best = points[most_symmetric(points)]
    return TargetCells(lowest, mask, cells, len(cells) / env.grid.size,
                       tuple(float(v) for v in best.round(6)))


def evaluations_to_target(result: Record, target: TargetCells) -> int | None:
    """The step at which the run first evaluated a target cell; None if it never did."""
    steps = [step for cell, step in result.best_cells.items() if target.mask[cell]]
    return min(steps) if steps else None
