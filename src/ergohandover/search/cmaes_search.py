"""CMA-ES (the ``cmaes`` package's ``CMA``) as an ask/tell searcher over the grid.

CMA-ES searches the unit cube: each axis's index coordinate divided by ``n − 1``, so the three
axes (41, 73 and 31 cells on the 1 cm grid) are scaled alike and one step size fits all. A
sample is snapped to its nearest cell; samples outside the cube are redrawn by the library (up
to 100 times, then clipped to the faces), so no proposal leaves the grid.

Settings and sources:

- population λ = 4 + ⌊3 ln 3⌋ = 7, the library's default, which is Hansen's (The CMA Evolution
  Strategy: A Tutorial, 2016, Table 1);
- start without a prior: the cube's centre with σ = 1/6, so that the whole cube lies within
  mean ± 3σ (pycma's documented rule for ``sigma0``: the optimum is expected within
  ``x0 ± 3·sigma0``);
- warm start: the prior's cell is the first member of the first generation and the mean, and
  the prior's SD per axis (in cube units) is the initial spread (σ = the largest, the
  covariance diagonal the ratios squared);
- restart from a uniformly random mean with σ = 1/6 (a new ``CMA``, seeded from the searcher's
  own seed sequence) when the library's stopping test fires or when a whole generation brought
  no new cell (the step size has shrunk below a cell: the search has converged on the grid).

A sample on a cell already evaluated is answered from memory: it still counts in its
generation, but not as an evaluation. Infeasible cells get :data:`INFEASIBLE` (CMA-ES uses only
the ranks within a generation).
"""

from __future__ import annotations

import math

import numpy as np

from ..landscape.grid import Grid
from .cells import NewCellSearcher, prior_point
from .prior import Prior

SIGMA0 = 1.0 / 6.0
"""Initial step size in cube units (see the module)."""
INFEASIBLE = 1e9
"""The value told for an infeasible cell: above every score, so it ranks last."""


class CMAESSearcher(NewCellSearcher):
    """CMA-ES with restarts over the unit cube of grid indices; see the module."""

    name = "cmaes"

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None):
        super().__init__(grid, seed, prior)
        starts, restarts = np.random.SeedSequence(self.seed).spawn(2)
        self._starts = starts  # one child per CMA instance
        self._rng = np.random.default_rng(restarts)  # restart means
        self._span = (self.shape - 1).astype(float)  # unit cube -> index coordinates
        self.restarts = 0
        if prior is None:
            self._start(np.full(3, 0.5))
        else:
            centre, sd = prior_point(grid, prior)
            unit_sd = sd / self._span
            self._start(centre / self._span, unit_sd)
            self._injected = centre / self._span  # the prior's own cell goes first

    def _start(self, mean: np.ndarray, spread: np.ndarray | None = None) -> None:
        from cmaes import CMA

        seed = int(self._starts.spawn(1)[0].generate_state(1)[0])
        bounds = np.array([[0.0, 1.0]] * 3)
        if spread is None:
            self._cma = CMA(mean=mean, sigma=SIGMA0, bounds=bounds, seed=seed)
        else:
            sigma = float(spread.max())
            self._cma = CMA(mean=mean, sigma=sigma, bounds=bounds, seed=seed,
                            cov=np.diag((spread / sigma) ** 2))
        self._generation: list[tuple[np.ndarray, float]] = []
        self._fresh = 0  # new cells in this generation
        self._injected: np.ndarray | None = None
        self._x: np.ndarray | None = None

    def _sample(self) -> np.ndarray:
        if self._injected is not None:
            x, self._injected = self._injected, None
            return x
        return self._cma.ask()

    def _propose(self) -> int:
        while True:
            x = self._sample()
            cell = self.snap(x * self._span)
            if cell not in self.told:
                self._x = x
                return cell
            self._add(x, self.told[cell], fresh=False)

    def _learn(self, cell: int, score: float) -> None:
        self._add(self._x, score, fresh=True)

    def _add(self, x: np.ndarray, score: float, fresh: bool) -> None:
        self._generation.append((x, INFEASIBLE if math.isinf(score) else score))
        self._fresh += fresh
        if len(self._generation) < self._cma.population_size:
            return
        stale = self._fresh == 0
        self._cma.tell(self._generation)
        self._generation, self._fresh = [], 0
        if stale or self._cma.should_stop():
            self.restarts += 1
            self._start(self._rng.random(3))
