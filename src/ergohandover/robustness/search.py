"""Locations of a landscape that keep their score when the posture is measured with error or the
box is delivered off target: the robust optimum (lowest expected score under posture error), the
location of largest margin to the band edges, and the score expected when the robot misses.

The landscape keeps only a few angles per cell, so the full posture of a cell is evaluated again
through the one evaluation path; the search is coarse to fine to keep that cheap: every
``stride``-th cell of the grid along each axis is screened with few draws (every cell measured
with the same errors, so that rankings are precise), then the grid's own cells around the best
screened ones are searched with many.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..ergonomics import Posture
from ..ergonomics.posture import POSTURE_COLUMNS
from ..landscape import Landscape
from ..landscape.grid import Grid
from ..landscape.stats import at_minimum, minimum, most_symmetric
from ..twin.evaluate import Evaluator, evaluate_arrays
from .margins import smallest_margin
from .posture_error import ErrorModel, expected_scores


def postures_at(points: np.ndarray, evaluator: Evaluator, workers: int = 1) -> tuple[
        Posture, np.ndarray]:
    """The twin's postures at ``points`` and which of them are feasible."""
    found = evaluate_arrays(points, evaluator, workers,
                            columns=("feasible", *POSTURE_COLUMNS))
    return Posture({c: found[c] for c in POSTURE_COLUMNS}), found["feasible"].astype(bool)


def coarse_cells(grid: Grid, stride: int) -> np.ndarray:
    """Flat indices of every ``stride``-th cell along each axis (the first cell included)."""
    index = np.ix_(*(np.arange(0, n, stride) for n in grid.shape))
    return np.ravel_multi_index(tuple(np.broadcast_arrays(*index)), grid.shape).ravel()


def neighbours(grid: Grid, cells: np.ndarray, radius: int) -> np.ndarray:
    """Every cell within ``radius`` cells (a cube) of any of ``cells``, on the grid, sorted."""
    offsets = np.stack(np.meshgrid(*[np.arange(-radius, radius + 1)] * 3, indexing="ij"),
                       axis=-1).reshape(-1, 3)
    around = (np.stack(np.unravel_index(cells, grid.shape), axis=-1)[:, None]
              + offsets[None]).reshape(-1, 3)
    inside = np.all((around >= 0) & (around < np.array(grid.shape)), axis=1)
    return np.unique(np.ravel_multi_index(tuple(around[inside].T), grid.shape))


@dataclass
class Search:
    """A coarse-to-fine search's result.

    Attributes:
        cell: the chosen flat index; location: its (3,) worker-frame location [m].
        value: its objective (expected score, or margin [deg]).
        screened: the screened cells (feasible ones) with their objective and nominal score:
            columns ``cell, x, y, z, nominal, value``.
    """

    cell: int
    location: np.ndarray
    value: float
    screened: pd.DataFrame


def _choose(grid: Grid, cells: np.ndarray, value: np.ndarray, nominal: np.ndarray) -> int:
    """The best cell: lowest value, then lowest nominal score, then the most symmetric."""
    best = np.isclose(value, value.min(), rtol=0, atol=1e-9)
    best &= nominal == nominal[best].min()
    chosen = cells[best]
    return int(chosen[most_symmetric(grid.coordinates(chosen))])


def robust_optimum(landscape: Landscape, evaluator: Evaluator, model: ErrorModel,
                   score: str, draws: int, seed: int, stride: int = 3,
                   screen_draws: int = 128, keep: int = 32, radius: int = 2,
                   workers: int = 1, include: np.ndarray | None = None,
                   tolerance: float | None = None) -> Search:
    """The cell of lowest expected ``score`` under posture error ``model``.

    Args:
        landscape: the worker's landscape (its grid and feasibility).
        evaluator: the worker the landscape belongs to.
        model: the posture-measurement error.
        score: the score to minimise in expectation.
        draws: measured copies per cell in the fine search (its expected scores are reported).
        seed: the errors' seed (screening and fine search draw their own from it).
        stride, screen_draws: the coarse screen (every ``stride``-th cell, ``screen_draws``).
        keep, radius: the fine search covers the cells within ``radius`` of the ``keep``
            best screened cells.
        workers: processes evaluating the twin.
        include: cells whose neighbourhoods the fine search also covers (the nominal
            optimum's, so that the robust optimum is never worse than it in expectation).
        tolerance: when given, only cells whose error-free ``score`` is within ``tolerance``
            of the landscape's minimum are candidates (0: the optimum's own cells), so that
            what measures best is not paid for by the worker's actual posture.
    """
    grid, feasible = landscape.grid, landscape.feasible.copy()
    if tolerance is not None:
        feasible &= landscape.arrays[score] <= minimum(landscape, score) + tolerance
    screen_seed, fine_seed = np.random.SeedSequence(seed).generate_state(2)
    cells = coarse_cells(grid, stride)
    cells = cells[feasible[cells]]
    if cells.size == 0:  # the candidates lie between the coarse cells: screen all of them
        cells = np.flatnonzero(feasible)
    posture, ok = postures_at(grid.coordinates(cells), evaluator, workers)
    expected = np.where(ok, expected_scores(posture, model, screen_draws, int(screen_seed),
                                            score, evaluator.scoring), np.inf)
    nominal = landscape.arrays[score][cells]
    screened = pd.DataFrame({"cell": cells, **dict(zip("xyz", grid.coordinates(cells).T,
                                                       strict=True)),
                             "nominal": nominal, "value": expected})
    best = cells[np.argsort(expected, kind="stable")[:keep]]
    extra = np.asarray([] if include is None else include, dtype=np.intp)
    fine = neighbours(grid, np.concatenate([best, extra]), radius)
    fine = fine[feasible[fine]]
    posture, ok = postures_at(grid.coordinates(fine), evaluator, workers)
    value = np.where(ok, expected_scores(posture, model, draws, int(fine_seed), score,
                                         evaluator.scoring), np.inf)
    cell = _choose(grid, fine, value, landscape.arrays[score][fine])
    return Search(cell, grid.coordinates([cell])[0], float(value[fine == cell][0]), screened)


def largest_margin(landscape: Landscape, evaluator: Evaluator, score: str, stride: int = 3,
                   keep: int = 16, radius: int = 2, workers: int = 1) -> Search:
    """Among the cells at the landscape's minimum of ``score``, the one whose smallest margin
    (over its angles, :func:`~.margins.smallest_margin`) is largest."""
    grid, values = landscape.grid, landscape.arrays[score]
    at_min = at_minimum(landscape, score)
    cells = coarse_cells(grid, stride)
    cells = cells[at_min[cells]]
    if cells.size == 0:  # the minimum lies between the coarse cells: search all its cells
        cells = np.flatnonzero(at_min)
    posture, ok = postures_at(grid.coordinates(cells), evaluator, workers)
    margin = np.where(ok, smallest_margin(posture, score, evaluator.scoring), -np.inf)
    screened = pd.DataFrame({"cell": cells, **dict(zip("xyz", grid.coordinates(cells).T,
                                                       strict=True)),
                             "nominal": values[cells], "value": margin})
    fine = neighbours(grid, cells[np.argsort(-margin, kind="stable")[:keep]], radius)
    fine = fine[at_min[fine]]
    posture, ok = postures_at(grid.coordinates(fine), evaluator, workers)
    margin = np.where(ok, smallest_margin(posture, score, evaluator.scoring), -np.inf)
    cell = _choose(grid, fine, -margin, values[fine])
    return Search(cell, grid.coordinates([cell])[0], float(margin[fine == cell][0]), screened)


def placement(landscape: Landscape, location: np.ndarray, radius_m: float, score: str,
              evaluator: Evaluator | None = None) -> dict[str, float]:
    """The score expected when the box arrives uniformly within ``radius_m`` of ``location``.

    The ball is the grid's lattice within the radius of the lattice point nearest ``location``:
    its cells are read from the landscape; those beyond the grid (a location at or past the
    boundary) are evaluated by ``evaluator``'s twin, or counted as cells it cannot take the box
    at when no evaluator is given.

    Returns:
        ``cells`` in the ball, ``mean`` score over its feasible cells, ``p_worse`` (the share of
        the ball scoring worse than the commanded cell) and ``share_infeasible`` (cells the twin
        cannot take the box at, or beyond the grid without an evaluator).
    """
    grid = landscape.grid
    reach = int(np.floor(radius_m / grid.step + 1e-9))
    steps = np.arange(-reach, reach + 1)
    offsets = np.stack(np.meshgrid(steps, steps, steps, indexing="ij"), axis=-1).reshape(-1, 3)
    offsets = offsets[np.linalg.norm(offsets * grid.step, axis=1) <= radius_m + 1e-9]
    cells = grid.nearest_index(location) + offsets
    inside = np.all((cells >= 0) & (cells < np.array(grid.shape)), axis=1)
    flat = np.ravel_multi_index(tuple(cells[inside].T), grid.shape)
    values = np.full(len(cells), np.nan)
    feasible = np.zeros(len(cells), dtype=bool)
    values[inside] = landscape.arrays[score][flat]
    feasible[inside] = landscape.feasible[flat]
    if evaluator is not None and not inside.all():
        found = evaluate_arrays(grid.boundary.lower + cells[~inside] * grid.step, evaluator,
                                columns=("feasible", score))
        values[~inside], feasible[~inside] = found[score], found["feasible"].astype(bool)
    nominal = values[np.flatnonzero(~offsets.any(axis=1))[0]]  # the commanded cell's
    taken = values[feasible]
    return {"cells": len(offsets), "mean": float(taken.mean()) if taken.size else np.nan,
            "p_worse": float((taken > nominal).sum() / len(offsets)),
            "share_infeasible": 1.0 - feasible.sum() / len(offsets)}
