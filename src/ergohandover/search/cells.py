"""Grid cells as the searchers see them, and the base of searchers that never ask twice.

Continuous optimisers (CMA-ES, particle swarms) and Optuna's samplers work on index
coordinates: a point ``(i, j, k)`` of floats within ``[0, n - 1]`` per axis, snapped to the
nearest cell. A population prior is given in metres; here it becomes a point and a spread in
grid steps.

Every evaluation is a real handover, and a repeat teaches nothing on a deterministic landscape
and little in the field, so :class:`NewCellSearcher` proposes only cells it has not been told
about: what an optimiser would re-propose is answered from memory inside the searcher, and
:class:`~.protocol.Evaluations` then counts one evaluation per ask.
"""

from __future__ import annotations

import math
from abc import abstractmethod

import numpy as np

from ..envs.scores import Answer
from ..errors import ConfigError
from ..landscape.grid import Grid
from .prior import Prior
from .protocol import AskTellSearcher, Recommendation, told
from .surrogate import surrogate_recommendation


def prior_point(grid: Grid, prior: Prior) -> tuple[np.ndarray, np.ndarray]:
    """The prior in index coordinates: its location (3,) clamped into the grid, and its SD
    (3,) in grid steps."""
    hi = np.asarray(grid.shape) - 1
    centre = (np.asarray(prior.location, float) - grid.boundary.lower) / grid.step
    return np.clip(centre, 0, hi), np.asarray(prior.sd, float) / grid.step


class NewCellSearcher(AskTellSearcher):
    """A searcher whose every ask is a cell not yet evaluated.

    Subclasses implement :meth:`_propose` (a cell not in :attr:`told`) and :meth:`_learn`.
    :meth:`ask` without a :meth:`tell` in between gives the same cell again (a session that
    stopped before the handover resumes there); :meth:`tell` must answer that cell.
    """

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None):
        super().__init__(grid, seed, prior)
        self.shape = np.asarray(grid.shape)
        self.told: dict[int, float] = {}  # cell -> score (inf: infeasible)
        self.heard: dict[int, Answer] = {}  # cell -> the whole answer it was told
        self._pending: int | None = None

    @property
    def cells(self) -> list[int]:
        """The cells it was told about, in order."""
        return list(self.told)

    @property
    def told_answers(self) -> list[float]:
        """What it was told about them, in order (scores, or a preference searcher's
        preferences)."""
        return list(self.told.values())

    def ask(self) -> int:
        if self._pending is None:
            if len(self.told) >= self.grid.size:
                raise ConfigError(f"searcher {self.name!r}: every one of the grid's "
                                  f"{self.grid.size} cells has been evaluated")
            self._pending = int(self._propose())
        return self._pending

    def tell(self, cell: int, answer: Answer | float) -> None:
        cell = int(cell)
        if cell != self._pending:
            asked = "nothing" if self._pending is None else f"cell {self._pending}"
            raise ConfigError(f"searcher {self.name!r}: told cell {cell}, but it asked for "
                              f"{asked} (tell answers the last ask)")
        answer = told(answer)
        self.told[cell], self.heard[cell] = answer.score, answer
        self._pending = None
        self._learn(cell, answer.score)

    def recommend(self) -> Recommendation:
        """Where it would hand over after what it was told: without a model of the worker of
        its own, the tried cell a model of its answers expects lowest
        (:func:`~.surrogate.surrogate_recommendation`; never the lowest single reading, which
        under measurement error favours a lucky one); a searcher with a model overrides this."""
        return Recommendation(surrogate_recommendation(self.grid, self.cells,
                                                       self.told_answers))

    @abstractmethod
    def _propose(self) -> int:
        """A flat cell not in :attr:`told`."""

    @abstractmethod
    def _learn(self, cell: int, score: float) -> None:
        """The answer at the cell :meth:`_propose` gave."""

    # -- geometry ------------------------------------------------------------------------------
    def snap(self, point) -> int:
        """The flat cell nearest ``point`` (3,) in index coordinates, clamped into the grid."""
        index = np.clip(np.rint(np.asarray(point, float)), 0, self.shape - 1).astype(int)
        return int(np.ravel_multi_index(tuple(index), self.grid.shape))

    def index(self, cell: int) -> np.ndarray:
        """(3,) integer index of a flat cell."""
        return np.array(np.unravel_index(int(cell), self.grid.shape))

    def nearest_new(self, point) -> int:
        """The cell nearest ``point`` (3,) [index coordinates] that has not been evaluated;
        ties go to the lowest flat index."""
        point = np.clip(np.asarray(point, float), 0, self.shape - 1)
        radius = 1
        while True:
            lo = np.maximum(np.floor(point - radius), 0).astype(int)
            hi = np.minimum(np.ceil(point + radius), self.shape - 1).astype(int)
            axes = [np.arange(a, b + 1) for a, b in zip(lo, hi, strict=True)]
            idx = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)  # (m, 3)
            cells = np.ravel_multi_index(tuple(idx.T), self.grid.shape)
            new = np.fromiter((c not in self.told for c in cells.tolist()), bool, len(cells))
            if new.any():
                d2 = ((idx[new] - point) ** 2).sum(axis=1)
                best = np.flatnonzero(d2 == d2.min())
                # Cells outside this cube lie farther than ``radius``: the nearest is certain.
                whole = np.all(lo == 0) and np.all(hi == self.shape - 1)
                if math.sqrt(d2.min()) <= radius or whole:
                    return int(cells[new][best].min())
                radius = math.ceil(math.sqrt(d2.min()))
            else:
                radius *= 2
