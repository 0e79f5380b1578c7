"""Bayesian optimisation (Optuna's GPSampler) and TPE (Optuna's TPESampler) as ask/tell
searchers over the grid.

The search space is the grid's integer index per axis (``IntDistribution(0, n - 1)`` for x, y
and z): every proposal is a cell, so nothing is snapped, and both samplers treat the axes as
ordered integers (the GP sampler searches its acquisition over them by line search, not by
rounding a continuous optimum).

**Infeasible cells are a constraint.** Every trial carries one constraint value (Optuna's
``Trial.set_constraint``; the ``constraints_func`` argument is deprecated since Optuna 5.0):
−1 where the worker took the box, +1 where they could not. Optuna also needs a finite objective
for an infeasible trial; it gets the worst (highest) feasible score seen so far. The GP sampler
fits its objective model to every trial, so that value says "at least as bad as anything seen",
which is what the edges of the reachable space are like (infeasible cells border the body and
the reach limit, where postures are worst), without an arbitrary constant that would stretch
the standardised scale; TPE ranks infeasible trials by their constraint alone and ignores the
value. Until the first feasible answer there is no such value: those trials stay open, which
the GP sampler treats as pending points (not proposed again) and TPE (``constant_liar`` off)
ignores.

**A proposal of a known cell** is answered from memory (its trial told the known score, so the
sampler learns it proposed a known cell) and replaced by the nearest cell not yet evaluated,
enqueued as the next trial: a practitioner would not repeat a handover.

**Warm start**: with a prior, the start-up design is the prior's: its cell, then
``PRIOR_DESIGN - 1`` distinct cells drawn from it (``study.enqueue_trial``), and the sampler's
model takes over after those ``PRIOR_DESIGN`` trials instead of after Optuna's 10 random ones.
Without a prior, Optuna's defaults stand.
"""

from __future__ import annotations

import math
from abc import abstractmethod
from collections.abc import Sequence

import numpy as np

from ..landscape.grid import Grid
from .cells import NewCellSearcher, prior_point
from .prior import Prior
from .protocol import finite_or_inf

AXES = ("x", "y", "z")
CONSTRAINT = "infeasible"
PRIOR_DESIGN = 5
"""Start-up trials drawn from the worker's prior (with one)."""


class OptunaSearcher(NewCellSearcher):
    """An Optuna study driven by ask/tell over the grid's indices; see the module."""

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None):
        import optuna
        from optuna.distributions import IntDistribution

        super().__init__(grid, seed, prior)
        optuna.logging.set_verbosity(optuna.logging.WARNING)  # no line per trial
        self.distributions = {a: IntDistribution(0, int(n) - 1)
                              for a, n in zip(AXES, grid.shape, strict=True)}
        # The Optuna study: read it for the trials; drive the search with ask/tell only.
        startup = None if prior is None else PRIOR_DESIGN
        self.study = optuna.create_study(direction="minimize", sampler=self._sampler(startup))
        if prior is not None:
            for index in self._prior_design(*prior_point(grid, prior)):
                self._enqueue(index)
        self._trial = None
        self._worst: float | None = None  # the highest feasible score told so far
        self._waiting: list = []  # infeasible trials told before any feasible one

    @abstractmethod
    def _sampler(self, startup: int | None):
        """The seeded Optuna sampler (``startup``: its start-up trials; None: its default)."""

    def _prior_design(self, centre: np.ndarray, sd: np.ndarray) -> list[np.ndarray]:
        """The prior's cell, then distinct cells drawn from N(centre, SD) (index units; a
        draw that lands on a chosen cell is drawn again, the spread growing by half each
        time all of a batch do)."""
        rng = np.random.default_rng([self.seed, PRIOR_DESIGN])
        chosen = [np.clip(np.rint(centre), 0, self.shape - 1).astype(int)]
        seen = {tuple(chosen[0])}
        spread = 1.0
        while len(chosen) < min(PRIOR_DESIGN, self.grid.size):
            points = np.clip(np.rint(rng.normal(centre, sd * spread, (16, 3))), 0,
                             self.shape - 1).astype(int)
            for index in points:
                if tuple(index) not in seen and len(chosen) < PRIOR_DESIGN:
                    seen.add(tuple(index))
                    chosen.append(index)
            spread *= 1.5
        return chosen

    def add_known(self, history: Sequence[tuple[int, float]]) -> None:
        """Answers obtained elsewhere (another session, a benchmark's history), added as
        completed trials without being proposed: the sampler learns from them, and
        :func:`~.protocol.replay` does not rebuild them. Infeasible answers need a feasible
        one (here or told before) for their objective value; until then they are only
        remembered (never proposed)."""
        import optuna

        answers = [(int(c), finite_or_inf(float(s))) for c, s in history]
        feasible = [s for _, s in answers if s < math.inf]
        if feasible:
            self._worst = max(feasible if self._worst is None else [*feasible, self._worst])
        trials = []
        for cell, score in answers:
            self.told[cell] = score
            ok = score < math.inf
            if not ok and self._worst is None:
                continue
            params = dict(zip(AXES, self.index(cell).tolist(), strict=True))
            trials.append(optuna.trial.create_trial(
                params=params, distributions=self.distributions,
                value=score if ok else self._worst, constraints={CONSTRAINT: -1.0 if ok else 1.0}))
        self.study.add_trials(trials)

    def _ask_trial(self):
        return self.study.ask(self.distributions)

    def _cell_of(self, trial) -> int:
        return self.snap([trial.params[a] for a in AXES])

    def _enqueue(self, point) -> None:
        index = np.clip(np.rint(np.asarray(point, float)), 0, self.shape - 1).astype(int)
        self.study.enqueue_trial(dict(zip(AXES, index.tolist(), strict=True)))

    def _propose(self) -> int:
        trial = self._ask_trial()
        cell = self._cell_of(trial)
        if cell in self.told:
            self._finish(trial, self.told[cell])
            self._enqueue(self.index(self.nearest_new(self.index(cell))))
            trial = self._ask_trial()
            cell = self._cell_of(trial)
        self._trial = trial
        return cell

    def _learn(self, cell: int, score: float) -> None:
        self._finish(self._trial, score)
        self._trial = None

    def _finish(self, trial, score: float) -> None:
        feasible = score < math.inf
        trial.set_constraint(CONSTRAINT, -1.0 if feasible else 1.0)
        if not feasible:
            if self._worst is None:
                self._waiting.append(trial)
            else:
                self.study.tell(trial, self._worst)
            return
        self._worst = score if self._worst is None else max(self._worst, score)
        self.study.tell(trial, score)
        for waiting in self._waiting:
            self.study.tell(waiting, self._worst)
        self._waiting.clear()


class GPSearcher(OptunaSearcher):
    """Bayesian optimisation: Optuna's GPSampler (Matérn-5/2 GP with ARD, log expected
    improvement, constrained by the feasibility GP), Optuna's defaults (10 random start-up
    trials without a prior), a noisy objective (a person's score is not deterministic)."""

    name = "bo"

    def _sampler(self, startup: int | None):
        from optuna.samplers import GPSampler

        if startup is None:
            return GPSampler(seed=self.seed)
        return GPSampler(seed=self.seed, n_startup_trials=startup)

    def _ask_trial(self):
        # One core, as every run: BLAS and torch's OpenMP otherwise contend for the two
        # cores (Optuna's own note on Linux): several times slower per trial here without it.
        # Optuna runs its GP inside ``with torch.device("cpu")``, a torch function mode that
        # sends every torch call through Python: on a CPU-only torch it changes nothing but
        # the time. With torch-function dispatch off the same operations run on the same
        # device, so the proposals are the same (tests/test_searchers.py) in less time
        # (experiments/bench_searchers.py measures it).
        import torch
        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=1), torch._C.DisableTorchFunction():
            return super()._ask_trial()


class TPESearcher(OptunaSearcher):
    """Optuna's TPESampler with its defaults (multivariate for one objective, 10 random
    start-up trials without a prior, 24 candidates per proposal); ``constant_liar`` off, as
    trials are sequential."""

    name = "tpe"

    def _sampler(self, startup: int | None):
        from optuna.samplers import TPESampler

        if startup is None:
            return TPESampler(seed=self.seed, constant_liar=False)
        return TPESampler(seed=self.seed, constant_liar=False, n_startup_trials=startup)
