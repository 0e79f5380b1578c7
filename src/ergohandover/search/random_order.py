"""Random order: uniformly random cells without replacement, the practitioner's baseline.

Every cell is equally likely to come next among those not yet tried, so a budget of n tries n
distinct cells in a uniformly random order (against random draws, :mod:`.walks`, which draw
with replacement and pay for a repeat).
"""

from __future__ import annotations

import numpy as np

from ..landscape.grid import Grid
from .cells import NewCellSearcher
from .prior import Prior


class RandomOrderSearcher(NewCellSearcher):
    """Uniform draws, a cell already tried drawn again; see the module."""

    name = "random-order"

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None):
        super().__init__(grid, seed, prior)
        self._rng = np.random.default_rng(self.seed)

    def _propose(self) -> int:
        while True:  # a repeat is rare: grids have ~10^4-10^6 cells against <= 10^3 asks
            cell = int(self._rng.integers(self.grid.size))
            if cell not in self.told:
                return cell

    def _learn(self, cell: int, score: float) -> None:
        """Nothing to learn: the order is fixed by the seed."""
