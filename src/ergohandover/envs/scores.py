"""Score sources: the objective E at a grid cell, read from a landscape or computed online.

Both sources answer ``score(flat_index) -> float`` with ``math.inf`` where the location is
infeasible, and give the same number for the same cell: a landscape is ``evaluate()`` of every
grid point, and ``evaluate()`` is deterministic and order-independent. What a search is told
of a cell is an :class:`Answer` (``answer(flat_index)``): the score, and what else the source
gave with it (the measured posture, how a person gave it).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import NamedTuple

import numpy as np

from ..ergonomics import OBJECTIVES
from ..errors import ConfigError
from ..landscape import Landscape, LandscapeError
from ..landscape.grid import Grid
from ..twin.evaluate import Evaluator, evaluate_arrays

LEXICOGRAPHIC = "lexicographic"
LEXICOGRAPHIC_ORDER = (("paper_postural", 1.0), ("reba_ab", 1e-2), ("rula", 1e-4),
                       ("trunk_flexion", 1e-6))
"""A landscape-only objective that ranks cells by the paper's score, then ``reba_ab``, then RULA,
then the most upright trunk (|trunk flexion| in whole degrees): their weighted sum. Each term is
an integer below 100 (``reba_ab`` at most 24, RULA 7, the trunk's degrees capped at 99; the
default worker's stay under 40), so a weight 100 times smaller than the one before never
outweighs a difference of one in an earlier term. With the env's symmetry term as the last
tie-break its best cells are a tiny share of the grid: a target on which a search budget binds."""
SCORE_MAX = {"paper_postural": 14, "reba": 15, "reba_ab": 24, "rula": 7,
             LEXICOGRAPHIC: 14 + 24e-2 + 7e-4 + 99e-6}
"""The largest value each objective can take (to normalise observations): the paper's score
2 neck + 4 trunk + 3 legs + 1 hands above the neck + 4 arm; REBA 15; Table A + Table B 12 + 12;
RULA 7."""


def check_objective(objective: str, lexicographic: bool = False) -> str:
    """``objective`` if it is one of :data:`OBJECTIVES` (or, where a landscape gives every
    score, :data:`LEXICOGRAPHIC`); a one-line ValueError otherwise."""
    allowed = (*OBJECTIVES, LEXICOGRAPHIC) if lexicographic else OBJECTIVES
    if objective not in allowed:
        raise ConfigError(f"objective = {objective!r} is not allowed (use "
                         f"{', '.join(allowed)})")
    return objective


def objective_values(landscape: Landscape, objective: str) -> np.ndarray:
    """The objective at every cell of ``landscape`` (float64, ``inf`` where infeasible)."""
    check_objective(objective, lexicographic=True)
    parts = LEXICOGRAPHIC_ORDER if objective == LEXICOGRAPHIC else ((objective, 1.0),)
    total = np.zeros(landscape.grid.size)
    for name, weight in parts:
        if name not in landscape.arrays:
            raise LandscapeError(f"the landscape has no '{name}' column")
        values = landscape.arrays[name].astype(np.float64)
        if name == "trunk_flexion":  # uprightness in whole degrees: an integer, like the scores
            values = np.minimum(np.rint(np.abs(values)), 99)  # never a whole step of RULA's
        total += weight * values
    return np.where(landscape.feasible, total, np.inf)


class Answer(NamedTuple):
    """What a search is told of one handover: the score (``math.inf``: infeasible; a
    searcher told preferences hears the preference here, :mod:`~..search.preferences`), how
    it was given (``score``, ``infeasible``, ``posture``, ``twin``, ``preference``), the answer
    as given (what a session records) and ``posture``, the angles behind it where the answer
    carried them (a measured posture, a posture row, a captured frame: NaN where unseen; the
    twin's), for a searcher that fits a twin to them."""

    score: float
    kind: str = "score"
    text: str = ""
    posture: dict[str, float] | None = None


class ScoreSource(ABC):
    """The objective at each cell of ``grid`` (flat C-order index, x slowest)."""

    grid: Grid
    objective: str
    answers: str = "scores"
    """What it answers: scores, or ``preferences`` (search/pairwise.py)."""

    @abstractmethod
    def score(self, flat: int) -> float:
        """The objective at cell ``flat``; ``math.inf`` if the location is infeasible."""

    def answer(self, flat: int) -> Answer:
        """What a search is told at cell ``flat``: its score, and what else came with it (a
        source whose answers carry more overrides this, and its ``score`` reads it)."""
        return Answer(self.score(flat))


class ArrayScores(ScoreSource):
    """Scores given as an array, one per cell in flat order (``inf`` or NaN: infeasible): a
    landscape's objective read once, or any table of scores.

    Args:
        grid: the cells.
        values: (grid.size,) the objective.
        objective: its name (an env's observation scale).
    """

    def __init__(self, grid: Grid, values: np.ndarray, objective: str = "paper_postural"):
        values = np.asarray(values, dtype=np.float64)
        if values.shape != (grid.size,):
            raise ConfigError(f"scores: shape {values.shape} does not match the grid's "
                              f"{grid.size} cells")
        self.grid, self.objective = grid, check_objective(objective, lexicographic=True)
        self._values = np.where(np.isnan(values), np.inf, values).tolist()  # list: fast reads

    def score(self, flat: int) -> float:
        return self._values[flat]


class LandscapeScores(ScoreSource):
    """Scores read from an exhaustive landscape: one list look-up per call.

    The landscape's int8 column is turned once into a Python list of shared float objects, because
    indexing a list is several times faster than indexing a numpy array from Python and this
    sits on the learners' hot path.
    """

    def __init__(self, landscape: Landscape, objective: str = "paper_postural"):
        self.grid = landscape.grid
        self.objective = check_objective(objective, lexicographic=True)
        if objective == LEXICOGRAPHIC:
            self._values = objective_values(landscape, objective).tolist()
            return
        if objective not in landscape.arrays:
            raise LandscapeError(f"the landscape has no '{objective}' column")
        values = landscape.arrays[objective]
        table = [float(v) for v in range(128)]  # int8 scores are 0..127; -1 is infeasible
        self._values = [math.inf if v < 0 else table[v]
                        for v in np.where(landscape.feasible, values, -1).tolist()]

    def score(self, flat: int) -> float:
        return self._values[flat]


class OnlineScores(ScoreSource):
    """Scores computed on demand with :func:`evaluate`, memoised per cell.

    A miss evaluates the whole aligned ``block``³ cube of cells containing the cell in one
    ``evaluate()`` call: a call's cost is mostly fixed, so 64 locations cost little more than
    one (experiments/bench_learning.py), and a learner that walks the grid uses its neighbours
    next. Because ``evaluate()`` is
    order-independent, the numbers are those of one call per cell.

    Args:
        grid: the cells.
        evaluator: the worker, task, solver and scoring settings.
        objective: one of :data:`OBJECTIVES`.
        block: cube edge [cells] evaluated together on a miss (1 = only the cell).
    """

    def __init__(self, grid: Grid, evaluator: Evaluator | None = None,
                 objective: str = "paper_postural", block: int = 4):
        if block < 1:
            raise ConfigError(f"block = {block} is outside the valid range (at least 1)")
        self.grid = grid
        self.evaluator = evaluator or Evaluator()
        self.objective = check_objective(objective)
        self.block = block
        self.evaluations = 0  # locations evaluated so far (misses x block size)
        self._memo: dict[int, float] = {}

    def score(self, flat: int) -> float:
        value = self._memo.get(flat)
        if value is None:
            self._fill(flat)
            value = self._memo[flat]
        return value

    def _fill(self, flat: int) -> None:
        cells = self.grid.aligned_block(flat, self.block)
        rows = evaluate_arrays(self.grid.coordinates(cells), self.evaluator,
                               columns=("flags", self.objective))
        feasible = rows["flags"] == 0
        values = rows[self.objective].astype(float)
        for c, ok, v in zip(cells.tolist(), feasible.tolist(), values.tolist(), strict=True):
            self._memo[c] = float(v) if ok else math.inf
        self.evaluations += len(cells)
