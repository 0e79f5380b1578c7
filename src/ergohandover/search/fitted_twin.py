"""A twin fitted to the worker from what is observed, and its optimum proposed.

The population prior predicts a worker's optimum from stature and sex alone. Two workers of one
stature still differ in their proportions, and a handover shows how this worker's body takes
the box: the posture at the first handovers. :class:`FittedTwinSearcher` proposes the prior's
cell and :data:`FIT` − 1 draws from the prior (as the prior alone does), then picks, among
candidate bodies of the survey's body model (:class:`TwinLibrary`), the one whose twin explains
those handovers best, and proposes that twin's cells from its lowest score up (equal scores:
nearest the prior first), never a cell twice.

"Explains best": the smallest mean squared difference between the angles measured at the
handovers and the candidate twin's angles at the same locations (every angle column of the
Posture table that was measured; a candidate that could not take the box where the worker did
scores :data:`MISSING_DEG`² for that handover), when the answers carry the measured posture
(the ``posture`` the searcher is told with each answer: a posture measured with error, a
posture row, a captured frame); otherwise — a rater's score — the smallest mean squared
difference between the answered scores and the candidate's.

The candidates are bodies, not settings: a worker whose twin differs in gaze or effort is fitted
by the body that mimics it best.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence

import numpy as np

from ..envs.scores import objective_values
from ..errors import ConfigError
from ..landscape.grid import Grid
from ..robustness.posture_error import ANGLE_COLUMNS
from ..twin.evaluate import Evaluator, evaluate_arrays
from .prior import Prior
from .prior_search import PriorSearcher

FIT = 3
"""Handovers drawn from the prior before the twin is fitted to them."""
MISSING_DEG = 90.0
"""The angle difference a candidate is charged, per angle, for a handover it could not take."""
SURVEY_DRAWS, CANDIDATES = 400, 12
"""Bodies drawn from the survey's model for a worker's sex, and how many of them (the nearest
in stature) are a session's candidates (:func:`survey_library`): each candidate's solver first
solves the warm-start lattice nodes its grid needs, which the person waits for at the fit."""


class TwinLibrary:
    """Candidate twins of one worker on one grid.

    Args:
        grid: the cells.
        evaluators: the candidates (bodies of the survey's model, the task and settings).
        values: ``values(i)``: candidate ``i``'s objective at every cell (``inf``: infeasible),
            computed or read when first needed (a landscape).
        names: the candidates' names (for the record, and the cache's keys).
        cache: where their solved angles are kept (shared by the libraries of one grid).
    """

    def __init__(self, grid: Grid, evaluators: Sequence[Evaluator],
                 values: Callable[[int], np.ndarray], names: Sequence[str] | None = None,
                 cache: dict | None = None):
        if not evaluators:
            raise ConfigError("a twin library needs at least one candidate")
        self.grid, self.evaluators, self._values = grid, list(evaluators), values
        self.names = list(names) if names is not None else [str(i) for i in
                                                            range(len(evaluators))]
        # (candidate's name, cell) -> its angles there: shared by libraries of one grid
        self._postures: dict[tuple[str, int], np.ndarray] = {} if cache is None else cache

    def __len__(self) -> int:
        return len(self.evaluators)

    def values(self, i: int) -> np.ndarray:
        return self._values(i)

    def angles(self, cells: Sequence[int]) -> np.ndarray:
        """(candidates, cells, angles) every candidate's angles at ``cells`` (NaN where it
        cannot take the box), solved when first asked for and kept."""
        cells = [int(c) for c in cells]
        for name, evaluator in zip(self.names, self.evaluators, strict=True):
            todo = [c for c in cells if (name, c) not in self._postures]
            if not todo:
                continue
            found = evaluate_arrays(self.grid.coordinates(todo), evaluator,
                                    columns=("feasible", *ANGLE_COLUMNS))
            for k, c in enumerate(todo):
                row = np.array([found[a][k] for a in ANGLE_COLUMNS], dtype=float)
                self._postures[(name, c)] = row if found["feasible"][k] else np.full(
                    len(ANGLE_COLUMNS), np.nan)
        return np.array([[self._postures[(name, c)] for c in cells] for name in self.names])


def fit(library: TwinLibrary, cells: Sequence[int], scores: Sequence[float],
        postures: Sequence[dict[str, float] | None]) -> tuple[int, np.ndarray]:
    """The candidate that explains the feasible handovers best (see the module; the first of
    equals) and every candidate's misfit. ``postures`` are used when every feasible handover
    has one, else ``scores``."""
    keep = [k for k, s in enumerate(scores) if math.isfinite(s)]
    if not keep:
        raise ConfigError("a twin is fitted to feasible handovers, and there is none")
    cells = [int(cells[k]) for k in keep]
    if all(postures[k] is not None for k in keep):
        measured = np.array([[postures[k][a] for a in ANGLE_COLUMNS] for k in keep])
        predicted = library.angles(cells)  # (candidates, handovers, angles)
        squared = np.where(np.isnan(predicted), MISSING_DEG ** 2,
                           (predicted - measured[None]) ** 2)
        seen = np.isfinite(measured)  # an angle the capture did not see is left out
        misfit = np.where(seen[None], squared, 0.0).sum(axis=(1, 2)) / max(seen.sum(), 1)
    else:
        observed = np.array([scores[k] for k in keep])
        predicted = np.array([library.values(i)[cells] for i in range(len(library))])
        misfit = np.where(np.isfinite(predicted), (predicted - observed) ** 2,
                          MISSING_DEG ** 2).mean(axis=1)
    return int(np.argmin(misfit)), misfit


class FittedTwinSearcher(PriorSearcher):
    """The prior's first :data:`FIT` proposals, then the fitted twin's cells; see the module.

    Args:
        grid, seed, prior: as every searcher's (the prior is needed).
        twins: the candidate twins.
    """

    name = "fitted-twin"

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None,
                 twins: TwinLibrary | None = None):
        super().__init__(grid, seed, prior)
        if twins is None:
            raise ConfigError("searcher fitted-twin needs candidate twins (a TwinLibrary)")
        self.twins = twins
        self.chosen: int | None = None
        self._order: list[int] = []

    def search(self, evaluations) -> dict:
        super().search(evaluations)
        return {"fitted_twin": None if self.chosen is None else self.twins.names[self.chosen]}

    def _propose(self) -> int:
        if self.chosen is None and len(self.cells) >= FIT and any(
                math.isfinite(s) for s in self.told_answers):
            self.chosen, _ = fit(self.twins, self.cells, self.told_answers, self.postures)
            self._order = self._ranked(self.twins.values(self.chosen))
        if self.chosen is None:
            return super()._propose()
        while self._order and self._order[-1] in self.told:
            self._order.pop()
        return self._order[-1] if self._order else self.nearest_new(self._centre)

    def _ranked(self, values: np.ndarray) -> list[int]:
        """The cells from the lowest score up (equal scores: nearest the prior first), as a
        stack (the next at the end)."""
        index = np.indices(self.grid.shape).reshape(3, -1).T
        distance = np.linalg.norm(index - self._centre, axis=1)
        order = np.lexsort((distance, np.where(np.isfinite(values), values, np.inf)))
        return order[::-1].tolist()

    @property
    def postures(self) -> list[dict[str, float] | None]:
        """The angles each answer carried, in the order told (None: a score alone)."""
        return [self.heard[c].posture for c in self.cells]


def survey_library(evaluator: Evaluator, grid: Grid, objective: str, seed: int,
                   progress: bool = True) -> TwinLibrary:
    """A worker's candidate twins for ``ergohandover personalise``: the twin the session was
    given, and the :data:`CANDIDATES` bodies nearest its stature among :data:`SURVEY_DRAWS`
    drawn from the survey's body model for its sex (seeded), with its task and settings. A
    candidate's landscape is swept (or read from the cache) only when the fit chooses it."""
    from ..landscape.store import landscape_of
    from ..twin.anthropometry import BodySpec

    body = evaluator.body
    drawn = BodySpec.sample(SURVEY_DRAWS, body.sex, np.random.default_rng([seed, SURVEY_DRAWS]))
    near = sorted(drawn, key=lambda b: abs(b.stature_m - body.stature_m))[:CANDIDATES]
    evaluators = [evaluator, *(dataclasses.replace(evaluator, body=b) for b in near)]
    names = ["the given worker", *(f"survey body {i + 1} ({b.stature_m:.3f} m)"
                                   for i, b in enumerate(near))]

    def values(i: int) -> np.ndarray:
        return objective_values(landscape_of(evaluators[i], grid, progress=progress), objective)

    return TwinLibrary(grid, evaluators, values, names)
