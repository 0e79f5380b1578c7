"""Particle-swarm optimisation as an ask/tell searcher over the grid, one particle at a time.

Omidi et al. (2023, Applied Sciences 13:5385) placed a cobot's end effector for a worker in VR
with PSO on a REBA-based posture measure. Its swarm size, inertia and acceleration coefficients
could not be read (only the paper's abstract was at hand), so the standard settings are used:

- inertia w = 0.7298 and c1 = c2 = 1.49618: Clerc & Kennedy's (2002) constriction coefficients
  (χ = 0.7298 with φ = 4.1, written as inertia-weight PSO);
- swarm of 13 particles: Standard PSO 2007's 10 + ⌊2√D⌋ for D = 3;
- global-best topology, synchronous updates (Kennedy & Eberhart's original scheme): a
  generation evaluates every particle, then all move;
- initial velocity (u − x)/2 with u drawn like the positions (Standard PSO 2007);
- walls: a particle that would leave the grid stops at the face and loses that velocity
  component (absorbing walls, as Standard PSO 2007 confines particles).

Particles live in index coordinates and are evaluated at their nearest cell. A particle on a
cell already evaluated is answered from memory (no evaluation); when a whole generation brings no
new cell the swarm has collapsed onto evaluated cells and is re-initialised uniformly (a
restart; the best cell found stays in the record, not in the swarm). With a prior, the first
swarm is drawn from N(prior, SD) in grid steps and particle 0 starts on the prior's cell.
"""

from __future__ import annotations

import numpy as np

from ..landscape.grid import Grid
from .cells import NewCellSearcher, prior_point
from .prior import Prior

INERTIA = 0.7298  # Clerc & Kennedy (2002)
C1 = C2 = 1.49618  # Clerc & Kennedy (2002)
SWARM = 10 + int(2 * np.sqrt(3))  # Standard PSO 2007: 10 + floor(2 sqrt(D)) = 13


class PSOSearcher(NewCellSearcher):
    """Global-best PSO with constriction settings and restarts; see the module."""

    name = "pso"

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None):
        super().__init__(grid, seed, prior)
        self._rng = np.random.default_rng(self.seed)
        self._hi = (self.shape - 1).astype(float)
        self.restarts = 0
        self._init_swarm(prior_point(grid, prior) if prior is not None else None)

    def _draw(self, prior) -> np.ndarray:
        if prior is None:
            return self._rng.uniform(0.0, self._hi, (SWARM, 3))
        centre, sd = prior
        return np.clip(self._rng.normal(centre, sd, (SWARM, 3)), 0.0, self._hi)

    def _init_swarm(self, prior=None) -> None:
        self._x = self._draw(prior)  # (SWARM, 3) positions [index coordinates]
        if prior is not None:
            self._x[0] = prior[0]
        self._v = (self._draw(prior) - self._x) / 2.0  # (SWARM, 3)
        self._best_x = self._x.copy()  # each particle's best position
        self._best_f = np.full(SWARM, np.inf)
        self._g = 0  # index of the swarm's best particle
        self._p = 0  # the particle to evaluate next
        self._fresh = 0  # new cells in this generation

    def _propose(self) -> int:
        while True:
            cell = self.snap(self._x[self._p])
            if cell not in self.told:
                return cell
            self._record(self.told[cell], fresh=False)

    def _learn(self, cell: int, score: float) -> None:
        self._record(score, fresh=True)

    def _record(self, score: float, fresh: bool) -> None:
        p = self._p
        if score < self._best_f[p]:
            self._best_f[p], self._best_x[p] = score, self._x[p]
            if score < self._best_f[self._g]:
                self._g = p
        self._fresh += fresh
        self._p += 1
        if self._p < SWARM:
            return
        if self._fresh == 0:
            self.restarts += 1
            self._init_swarm()
            return
        self._p, self._fresh = 0, 0
        self._move()

    def _move(self) -> None:
        r1, r2 = self._rng.random((2, SWARM, 3))
        self._v = (INERTIA * self._v + C1 * r1 * (self._best_x - self._x)
                   + C2 * r2 * (self._best_x[self._g] - self._x))
        x = self._x + self._v
        out = (x < 0.0) | (x > self._hi)
        self._x = np.clip(x, 0.0, self._hi)
        self._v[out] = 0.0
