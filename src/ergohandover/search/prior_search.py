"""The population prior alone as a searcher: what the prior is worth without any optimiser.

First the prior's own cell (its location snapped to the nearest cell, clamped into the grid),
then draws from N(location, SD) snapped to cells, never a cell twice. It learns nothing from the
scores: any searcher that uses the prior as a warm start should beat it.
"""

from __future__ import annotations

import numpy as np

from ..errors import ConfigError
from ..landscape.grid import Grid
from .cells import NewCellSearcher, prior_point
from .prior import Prior

DRAWS = 64
"""Candidates drawn at once; the first untried one is proposed."""
WIDEN = 2.0
"""When a whole block of draws lands on tried cells (the prior's cells near its centre are used
up), the spread is multiplied by this, so the search moves outward instead of stalling; once
it is wider than the grid, cells are drawn uniformly."""


class PriorSearcher(NewCellSearcher):
    """Draws from the worker's prior, nearest cells first in probability; see the module."""

    name = "prior"

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None):
        if prior is None:
            raise ConfigError("searcher prior needs a worker's prior (a population prior's "
                              "location and SD; use another searcher without one)")
        super().__init__(grid, seed, prior)
        self._rng = np.random.default_rng(self.seed)
        self._centre, self._sd = prior_point(grid, prior)
        self._spread = 1.0

    def _propose(self) -> int:
        first = self.snap(self._centre)
        if first not in self.told:
            return first
        hi = self.shape - 1
        while True:
            if (self._sd * self._spread).min() > self.shape.max():  # wider than the grid:
                cells = self._rng.integers(self.grid.size, size=DRAWS).tolist()  # uniform
            else:
                points = self._rng.normal(self._centre, self._sd * self._spread, (DRAWS, 3))
                index = np.clip(np.rint(points), 0, hi).astype(int)  # (DRAWS, 3)
                cells = np.ravel_multi_index(tuple(index.T), self.grid.shape).tolist()
            for cell in cells:
                if cell not in self.told:
                    return cell
            self._spread *= WIDEN

    def _learn(self, cell: int, score: float) -> None:
        """The prior does not change with the answers."""
