"""Scores as a site measures them: each handover's posture read with measurement error, or
its score given by a rater who is not perfectly consistent.

In the field nobody reads the twin's exact score off a worker. Whoever watches a handover
measures the posture (video, IMUs) to a few degrees and scores what they measured. Here a
handover at a cell is answered by the twin's posture there, every measured angle carrying the
robustness part's error (:class:`~ergohandover.robustness.posture_error.ErrorModel`: one draw
per handover, from the source's own generator), scored with the evaluator's settings. Two
handovers at one cell are two measurements. With an error of 0 the answers are the twin's
scores exactly.

The postures are solved when a cell is first asked for, in aligned cubes of ``block``³ cells
(as :class:`~ergohandover.envs.scores.OnlineScores`), and kept. Measuring them is vectorised
scoring of one posture. Each answer carries the angles measured at that handover (what a
searcher that fits a twin to the worker reads: :mod:`~ergohandover.search.fitted_twin`).

A rater watching the handover gives its score directly (:class:`RatedScores`): the worker's
error-free score plus a Gaussian error, rounded to a whole score (a rater writes whole scores)
and never below 1. The error's SD comes from the rater's intra-rater reliability: with the
intraclass correlation ICC = V / (V + s²) of a rater scoring the same postures twice, where V
is the spread of the scores being rated, s = √(V (1 − ICC) / ICC) (:func:`rater_sd`). Here V is
the variance of the worker's own score over the feasible cells of the grid: the rater's error
is as large, relative to the spread of what they rate, as in the reliability study.
"""

from __future__ import annotations

import math

import numpy as np

from ...envs.scores import Answer, ScoreSource
from ...ergonomics import Posture, score_postures
from ...ergonomics.posture import POSTURE_COLUMNS
from ...errors import ConfigError
from ...landscape.grid import Grid
from ...robustness.measured_error import MeasuredError
from ...robustness.posture_error import ErrorModel, angles_of, perturbed
from ...twin.evaluate import Evaluator, evaluate_arrays

MEASURED = ("paper_postural", "reba", "reba_ab", "rula")
"""The objectives a measured posture gives (a landscape-only objective is not measured)."""


class MeasuredScores(ScoreSource):
    """The score measured at each handover; see the module.

    Args:
        grid: the cells.
        evaluator: the worker (the twin whose postures are measured) and the scoring settings.
        objective: one of :data:`MEASURED`.
        model: the measurement error.
        rng: the errors' generator (one per source: its own stream of measurements).
        block: cube edge [cells] of postures solved together on a miss (1: only the cell).
        postures: cell -> posture (None: infeasible) solved before for this worker and grid,
            shared with other sources of the same worker (filled as cells are solved).
    """

    def __init__(self, grid: Grid, evaluator: Evaluator, objective: str,
                 model: ErrorModel | MeasuredError,
                 rng: np.random.Generator, block: int = 1,
                 postures: dict[int, dict[str, float] | None] | None = None):
        if objective not in MEASURED:
            raise ConfigError(f"objective = {objective!r} is not allowed for measured answers "
                              f"(use {', '.join(MEASURED)})")
        if block < 1:
            raise ConfigError(f"block = {block} is outside the valid range (at least 1)")
        self.grid, self.evaluator, self.objective = grid, evaluator, objective
        self.model, self.rng, self.block = model, rng, block
        self.measurements = 0  # handovers measured so far
        self._postures = {} if postures is None else postures  # None: infeasible

    def score(self, flat: int) -> float:
        return self.answer(flat).score

    def answer(self, flat: int) -> Answer:
        """The score measured at cell ``flat`` with the angles measured (one handover)."""
        posture = self.posture(flat)
        self.measurements += 1
        if posture is None:
            return Answer(math.inf, "infeasible")  # nobody measures what cannot be taken
        measured = perturbed(Posture({c: np.array([v]) for c, v in posture.items()}),
                             self.model, 1, self.rng)
        score = float(score_postures(measured, self.evaluator.scoring)[self.objective][0])
        return Answer(score, "posture", posture=angles_of(measured))

    def posture(self, flat: int) -> dict[str, float] | None:
        """The twin's error-free posture at cell ``flat`` (None where it cannot take the
        box)."""
        flat = int(flat)
        if flat not in self._postures:
            self._solve(flat)
        return self._postures[flat]

    def _solve(self, flat: int) -> None:
        cells = self.grid.aligned_block(flat, self.block)
        found = evaluate_arrays(self.grid.coordinates(cells), self.evaluator,
                                columns=("feasible", *POSTURE_COLUMNS))
        for i, c in enumerate(cells.tolist()):
            self._postures[c] = ({name: float(found[name][i]) for name in POSTURE_COLUMNS}
                                 if found["feasible"][i] else None)


def rater_sd(values: np.ndarray, icc: float) -> float:
    """The SD [score points] of a rater's error whose intraclass correlation over ``values``
    (the scores being rated; ``inf``: infeasible, left out) is ``icc``; see the module."""
    if not 0 < icc <= 1:
        raise ConfigError(f"icc = {icc!r} is outside the valid range (0, 1]")
    finite = np.asarray(values, dtype=float)
    finite = finite[np.isfinite(finite)]
    if finite.size < 2:
        raise ConfigError("a rater's error needs at least 2 feasible scores to scale to")
    return float(np.sqrt(finite.var() * (1 - icc) / icc))


class RatedScores(ScoreSource):
    """The score a rater gives at each handover; see the module.

    Args:
        grid: the cells.
        values: (grid.size,) the worker's error-free score (``inf``: infeasible).
        sd: the rater's error [score points] (:func:`rater_sd`).
        rng: the errors' generator.
        objective: the score's name.
    """

    def __init__(self, grid: Grid, values: np.ndarray, sd: float, rng: np.random.Generator,
                 objective: str = "paper_postural"):
        if not (math.isfinite(sd) and sd >= 0):
            raise ConfigError(f"rater sd = {sd!r} is outside the valid range (>= 0)")
        self.grid, self.values, self.sd, self.rng = grid, np.asarray(values, float), sd, rng
        self.objective = objective
        self.measurements = 0

    def score(self, flat: int) -> float:
        self.measurements += 1
        true = float(self.values[int(flat)])
        if not math.isfinite(true):
            return math.inf
        return float(max(1.0, round(true + self.sd * self.rng.standard_normal())))
