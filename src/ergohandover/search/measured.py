"""Scores as a site measures them: each handover's posture read with measurement error.

In the field nobody reads the twin's exact score off a worker. Whoever watches a handover
measures the posture (video, IMUs) to a few degrees and scores what they measured. Here a
handover at a cell is answered by the twin's posture there, every measured angle carrying the
robustness part's error (:class:`~ergohandover.robustness.posture_error.ErrorModel`: one draw
per handover, from the source's own generator), scored with the evaluator's settings. Two
handovers at one cell are two measurements. With an error of 0 the answers are the twin's
scores exactly.

The postures are solved when a cell is first asked for, in aligned cubes of ``block``³ cells
(as :class:`~ergohandover.envs.scores.OnlineScores`), and kept. Measuring them is vectorised
scoring of one posture.
"""

from __future__ import annotations

import math

import numpy as np

from ..envs.scores import ScoreSource
from ..ergonomics import Posture, score_postures
from ..ergonomics.posture import POSTURE_COLUMNS
from ..errors import ConfigError
from ..landscape.grid import Grid
from ..robustness.posture_error import ErrorModel, perturbed
from ..twin.evaluate import Evaluator, evaluate_arrays

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

    def __init__(self, grid: Grid, evaluator: Evaluator, objective: str, model: ErrorModel,
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
        posture = self.posture(flat)
        self.measurements += 1
        if posture is None:
            return math.inf  # nobody measures a handover the worker cannot take
        measured = perturbed(Posture({c: np.array([v]) for c, v in posture.items()}),
                             self.model, 1, self.rng)
        return float(score_postures(measured, self.evaluator.scoring)[self.objective][0])

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
