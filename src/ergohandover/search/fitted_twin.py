"""A twin fitted to the worker from every measured angle, and the location its model expects to
be the worker's optimum.

The population prior predicts a worker's optimum from stature and sex alone. Two workers of one
stature still differ in their proportions, and each handover shows how this worker's body takes
the box. :class:`FittedTwinSearcher` keeps a posterior over **hypotheses** of who the worker is:
a candidate body (:class:`TwinLibrary`, bodies of the survey's model, each with its twin's
landscape) displaced by a few centimetres up and forward (:data:`SHIFT_RANGE_M`), because a
worker slightly taller or shorter than the nearest candidate takes the box alike a little higher
or lower. A hypothesis says, for every cell, what the worker's angles and score are there (the
candidate's at the displaced cell) and where the worker's optimum lies (the candidate's, moved).

- **Prior** over hypotheses: candidates of the worker's sex, weighted by how close their stature
  is (:data:`STATURE_BANDWIDTH_M`) and less if a joint of theirs is restricted
  (:data:`RESTRICTED_PRIOR`); displacements centred where the population prior's slope
  moves an optimum for the stature difference (:attr:`~.prior.Prior.per_metre`), spread
  :data:`SHIFT_SD_M`.
- **Likelihood** of each handover: every angle the answer measured that a landscape holds
  (:data:`FIELD_ANGLES`; NaN: unseen, left out), less the instrument's bias, against the
  hypothesis's angles there, jointly Gaussian with the instrument's covariance (its SDs and the
  correlation of errors one sensor shares: :func:`angle_error`) and the bodies' own spread
  (:data:`BODY_SD_DEG`) added on each angle; an answer of a score alone, Gaussian on the score
  (:data:`SCORE_SD`); a hypothesis wrong about whether the worker could take the box there is
  charged :data:`FEASIBILITY_MISS`.
- **Recommendation** (:meth:`FittedTwinSearcher.recommend`): the cell with the highest posterior
  probability of being the worker's optimum, and that probability; a single low reading moves
  it only as far as it moves the posterior.
- **Proposal**: that cell while it is untried, else the untried cell of highest probability
  (equal: nearest the prior).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from ..envs.scores import Answer, objective_values
from ..errors import ConfigError
from ..landscape import Landscape
from ..landscape.grid import Grid
from ..landscape.sweep import ANGLES as LANDSCAPE_ANGLES
from ..robustness.measured_error import MEASURED_ERROR, MeasuredError
from ..robustness.posture_error import ANGLE_COLUMNS, PAIRED, ErrorModel
from ..twin.evaluate import Evaluator
from .cells import NewCellSearcher, prior_point
from .prior import Prior
from .protocol import Recommendation

STATURE_BANDWIDTH_M = 0.03
"""How fast a candidate's prior weight falls with its stature's distance from the worker's
(the SD of a Gaussian kernel) [m]."""
SHIFT_AXES = (1, 2)
"""The grid's axes a hypothesis displaces the candidate along: up (y) and forward (z) of the
worker frame, where an optimum moves with stature; sideways it stays on the midline."""
SHIFT_RANGE_M, SHIFT_SD_M = 0.03, 0.015
"""The largest displacement per axis [m] and the spread of its prior about the stature slope's
[m]: chosen on the population's workers 31-60, not the study's 30 (docs/personalise.md)."""
BODY_SD_DEG = 3.0
"""How far a worker's angle may lie from the best hypothesis's even without measurement error
[deg] (bodies differ by more than stature and a displacement): added in quadrature to the
instrument's SD."""
SCORE_SD = 1.0
"""The spread of a score answered alone about the hypothesis's score [points]: a banded score
that flips by one point."""
FEASIBILITY_MISS = math.log(1e-3)
"""The log-probability a hypothesis is charged for a handover whose feasibility it got wrong
(the worker took the box where the candidate could not, or the reverse): the reach boundary
differs between bodies by about a cell, so it excludes a hypothesis without ending it."""
RESTRICTED_PRIOR = 0.1
"""A candidate with a restricted joint (an impaired body) starts with this share of the prior
weight of an unrestricted one of its stature: most workers move every joint through its full
range (an assumption, not a prevalence); the angles a restriction changes move it from there."""
PRUNE = 1e-9
"""Hypotheses lighter than this share of the heaviest are left out of the optimum's
probability."""
SURVEY_DRAWS, CANDIDATES = 400, 12
"""Bodies drawn from the survey's model for a worker's sex, and how many of them (the nearest
in stature) are a session's candidates (:func:`survey_library`)."""


FIELD_ANGLES = tuple(a for a in LANDSCAPE_ANGLES if a != "hand_error_m")
"""The angles a candidate's landscape holds at every cell, and so the angles a hypothesis is
compared on: the trunk's flexion, side bend and twist, the neck's flexion, the knee's, and
both upper arms' flexion and elbows. The others a measured answer carries would need each
candidate's posture solved at every handover."""


def angle_error(error: ErrorModel | MeasuredError) -> tuple[np.ndarray, np.ndarray]:
    """An instrument's bias (:data:`FIELD_ANGLES`,) [deg] and the covariance of its errors
    (:data:`FIELD_ANGLES` squared) [deg²]: an IMU suit's errors are correlated within a
    segment and between sides, so ten handovers' trunk angles are not ten independent
    readings of each."""
    index = [ANGLE_COLUMNS.index(a) for a in FIELD_ANGLES]
    if isinstance(error, MeasuredError):
        sd = error.sd()[index]
        return error.bias()[index], error.correlation()[np.ix_(index, index)] * np.outer(sd, sd)
    same = np.eye(len(index))
    if error.structure == "bilateral":  # one draw for both sides of a paired angle
        for right, left in PAIRED.items():
            if right in FIELD_ANGLES and left in FIELD_ANGLES:
                i, j = FIELD_ANGLES.index(right), FIELD_ANGLES.index(left)
                same[i, j] = same[j, i] = 1.0
    return np.zeros(len(index)), same * error.sd_deg ** 2


def named_error(name: str) -> ErrorModel | MeasuredError:
    """An instrument by name: ``imu`` (the published IMU suit's error,
    :data:`~..robustness.measured_error.MEASURED_ERROR`) or an SD in degrees on every angle."""
    return MEASURED_ERROR if name == "imu" else ErrorModel(float(name))


class TwinLibrary:
    """Candidate twins of one worker on one grid.

    Args:
        grid: the cells.
        evaluators: the candidates (bodies of the survey's model, the task and settings).
        landscape: ``landscape(i)``: candidate ``i``'s landscape on ``grid`` (read from the
            cache or swept when first needed).
        objective: the score the worker's optimum is the lowest of.
        names: the candidates' names (for the record, and the cache's keys).
        cache: where their scores and angles are kept by name (shared by the libraries of
            one grid).
        worker: the worker's stature [m] and sex (a site knows them), or None: the first
            candidate's.
        angle_sd_deg: the SD of the instrument that measures the answers' angles [deg]: one
            for every angle, or each angle's by name (an angle not named: the largest given).
        error: the instrument's error model, when known (its bias and covariance replace
            ``angle_sd_deg``: :func:`angle_error`).
    """

    def __init__(self, grid: Grid, evaluators: Sequence[Evaluator],
                 landscape: Callable[[int], Landscape], objective: str,
                 names: Sequence[str] | None = None, cache: dict | None = None,
                 worker: tuple[float, str] | None = None,
                 angle_sd_deg: float | Mapping[str, float] = 5.0,
                 error: ErrorModel | MeasuredError | None = None):
        if not evaluators:
            raise ConfigError("a twin library needs at least one candidate")
        given = dict(angle_sd_deg) if isinstance(angle_sd_deg, Mapping) else {
            a: angle_sd_deg for a in FIELD_ANGLES}
        for name, sd in given.items():
            if not (math.isfinite(sd) and sd >= 0):
                raise ConfigError(f"angle_sd_deg = {sd!r} ({name}) is outside the valid range "
                                  "(>= 0)")
        self.grid, self.evaluators, self._landscape = grid, list(evaluators), landscape
        self.objective = objective
        self.names = list(names) if names is not None else [str(i) for i in
                                                            range(len(evaluators))]
        self._kept: dict[tuple[str, str], np.ndarray] = {} if cache is None else cache
        first = self.evaluators[0].body
        self.worker = worker or (first.stature_m, first.sex)
        widest = max(given.values(), default=0.0)
        self.angle_bias_deg, self.angle_covariance = (np.zeros(len(FIELD_ANGLES)), np.diag(
            [float(given.get(a, widest)) ** 2 for a in FIELD_ANGLES])) if error is None else \
            angle_error(error)
        """(:data:`FIELD_ANGLES`,) the instrument's bias [deg] and (:data:`FIELD_ANGLES`
        squared) the covariance of its errors [deg²]."""

    def __len__(self) -> int:
        return len(self.evaluators)

    def _read(self, i: int) -> None:
        found = self._landscape(i)
        values = objective_values(found, self.objective)
        name = self.names[i]
        self._kept[(name, self.objective)] = values
        self._kept[(name, "optimum")] = np.flatnonzero(values == values.min())
        field = np.column_stack([found.arrays[a] for a in FIELD_ANGLES]).astype(np.float32)
        field[~found.feasible] = np.nan
        self._kept[(name, "angles")] = field

    def _get(self, i: int, what: str) -> np.ndarray:
        key = (self.names[i], what)
        if key not in self._kept:
            self._read(i)
        return self._kept[key]

    def prepare(self) -> None:
        """Read every candidate now (a process that forks workers afterwards shares them)."""
        for i in range(len(self)):
            self._get(i, "angles")

    def values(self, i: int) -> np.ndarray:
        """Candidate ``i``'s objective at every cell (``inf``: infeasible)."""
        return self._get(i, self.objective)

    def optimum(self, i: int) -> np.ndarray:
        """Candidate ``i``'s optimum: the flat cells at its lowest score."""
        return self._get(i, "optimum")

    def angles(self, cells: Sequence[int], which: Sequence[int] | None = None) -> np.ndarray:
        """(candidates, cells, :data:`FIELD_ANGLES`) the angles of every candidate (or those
        ``which`` names) at ``cells`` (NaN where it cannot take the box)."""
        chosen = range(len(self)) if which is None else which
        cells = np.asarray(cells, dtype=np.intp)
        return np.stack([self._get(int(i), "angles")[cells] for i in chosen]) if len(
            chosen) else np.zeros((0, len(cells), len(FIELD_ANGLES)))


class BodyPosterior:
    """The posterior over hypotheses (candidate x displacement) of one worker; see the module.

    Args:
        library: the candidates.
        prior: the worker's population prior (its ``per_metre`` slope centres the
            displacements; without one they are centred on none).
    """

    def __init__(self, library: TwinLibrary, prior: Prior | None):
        self.library, grid = library, library.grid
        self.shape = np.asarray(grid.shape)
        reach = [math.floor(SHIFT_RANGE_M / grid.step + 1e-9) if a in SHIFT_AXES else 0
                 for a in range(3)]
        steps = np.stack(np.meshgrid(*(np.arange(-r, r + 1) for r in reach), indexing="ij"),
                         axis=-1).reshape(-1, 3)
        self.shifts = steps  # (D, 3) cells: the worker's field at c is the candidate's at c - d
        stature, sex = library.worker
        bodies = [e.body for e in library.evaluators]
        same = np.array([b.sex == sex for b in bodies])
        if not same.any():
            same[:] = True  # no candidate of the worker's sex: every candidate, by stature
        difference = stature - np.array([b.stature_m for b in bodies])  # (K,) [m]
        slope = np.zeros(3) if prior is None or prior.per_metre is None else \
            np.asarray(prior.per_metre, float)
        expected = difference[:, None] * slope[None, :]  # (K, 3) [m]
        offset = steps[None, :, :] * grid.step - expected[:, None, :]  # (K, D, 3) [m]
        axes = list(SHIFT_AXES)
        self.log_weight = (-0.5 * (difference / STATURE_BANDWIDTH_M) ** 2)[:, None] \
            - 0.5 * ((offset[:, :, axes] / SHIFT_SD_M) ** 2).sum(axis=2)
        restricted = np.array([bool(b.restrictions) for b in bodies])
        self.log_weight[restricted] += math.log(RESTRICTED_PRIOR)
        self.log_weight[~same] = -np.inf
        self._p_optimal: np.ndarray | None = None
        self.covariance = library.angle_covariance + np.eye(len(FIELD_ANGLES)) * BODY_SD_DEG ** 2

    @property
    def weights(self) -> np.ndarray:
        """(K, D) the hypotheses' posterior probabilities."""
        w = np.exp(self.log_weight - self.log_weight.max())
        return w / w.sum()

    def candidate_weights(self) -> np.ndarray:
        """(K,) each candidate's posterior probability, its displacements summed."""
        return self.weights.sum(axis=1)

    def sources(self, cell: int) -> tuple[np.ndarray, np.ndarray]:
        """The candidate's cell under each displacement for the worker's ``cell``: (D,) flat
        cells (clamped) and (D,) whether it lies on the grid."""
        index = np.array(np.unravel_index(int(cell), tuple(self.shape)))[None, :] - self.shifts
        inside = ((index >= 0) & (index < self.shape)).all(axis=1)
        clamped = np.clip(index, 0, self.shape - 1)
        return np.ravel_multi_index(tuple(clamped.T), tuple(self.shape)), inside

    def update(self, cell: int, answer: Answer) -> None:
        """Weigh every hypothesis by how well it explains the answer at ``cell``."""
        sources, inside = self.sources(cell)
        # Hypotheses already negligible are dropped for good (their candidates are never read
        # again).
        live = self.log_weight > self.log_weight.max() + math.log(PRUNE)
        alive = np.flatnonzero(live.any(axis=1))
        feasible_worker = math.isfinite(answer.score)
        posture = answer.posture if feasible_worker else None
        step = np.zeros_like(self.log_weight)
        if posture is not None and any(math.isfinite(posture.get(a, math.nan))
                                       for a in FIELD_ANGLES):
            measured = np.array([posture.get(a, math.nan) for a in FIELD_ANGLES], float)
            seen = np.isfinite(measured)
            predicted = self.library.angles(sources, alive)  # (alive, D, angles)
            feasible = ~np.isnan(predicted).all(axis=2) & inside[None, :]
            residual = np.nan_to_num(predicted[..., seen] - (
                measured - self.library.angle_bias_deg)[seen], nan=0.0)
            precision = np.linalg.inv(self.covariance[np.ix_(seen, seen)])
            fit = -0.5 * np.einsum("kdi,ij,kdj->kd", residual, precision, residual)
            step[alive] = np.where(feasible, fit, FEASIBILITY_MISS)
        else:
            values = np.array([self.library.values(int(k))[sources] for k in alive])
            feasible = np.isfinite(values) & inside[None, :]
            if feasible_worker:
                fit = -0.5 * ((np.where(feasible, values, 0.0) - answer.score) / SCORE_SD) ** 2
                step[alive] = np.where(feasible, fit, FEASIBILITY_MISS)
            else:
                step[alive] = np.where(feasible, FEASIBILITY_MISS, 0.0)
        self.log_weight = np.where(live, self.log_weight + step, -np.inf)
        self._p_optimal = None

    def expected_scores(self, cells: Sequence[int]) -> np.ndarray:
        """(len(cells),) the worker's expected objective at each cell under the posterior, of
        the hypotheses that can take the box there (``inf``: none can)."""
        weights = self.weights
        live = np.flatnonzero(weights.max(axis=1) > PRUNE * weights.max())
        found = []
        for cell in cells:
            sources, inside = self.sources(int(cell))
            values = np.array([self.library.values(int(k))[sources] for k in live])
            feasible = np.isfinite(values) & inside[None, :]
            share = np.where(feasible, weights[live], 0.0)
            found.append(float((share * np.where(feasible, values, 0.0)).sum() / share.sum())
                         if share.sum() > 0 else math.inf)
        return np.array(found)

    def optimum_of(self, candidate: int) -> tuple[np.ndarray, np.ndarray]:
        """A candidate's optimum as flat cells and the share of the candidate's weight each
        holds: every cell at its lowest score, each wholly."""
        cells = self.library.optimum(candidate)
        return cells, np.ones(len(cells))

    def p_optimal(self) -> np.ndarray:
        """(grid.size,) each cell's posterior probability of being the worker's optimum: the
        summed weight of the hypotheses whose optimum includes it (an optimum is a plateau of
        cells, every one of them the optimum)."""
        if self._p_optimal is None:
            weights = self.weights
            live = np.flatnonzero(weights.max(axis=1) > PRUNE * weights.max())
            optima = [self.optimum_of(int(k)) for k in live]
            cells = np.concatenate([c for c, _ in optima])
            share = np.concatenate([s for _, s in optima])
            owner = np.repeat(live, [len(c) for c, _ in optima])
            shape = tuple(int(n) for n in self.shape)
            total = np.zeros(shape)
            # Per displacement, every candidate's optimum weighed at once, then moved by it.
            for d, shift in enumerate(self.shifts):
                field = np.bincount(cells, weights[owner, d] * share, minlength=total.size)
                pairs = list(zip(shift.tolist(), shape, strict=True))
                source = tuple(slice(max(0, -m), n - max(0, m)) for m, n in pairs)
                target = tuple(slice(max(0, m), n - max(0, -m)) for m, n in pairs)
                total[target] += field.reshape(shape)[source]
            self._p_optimal = np.minimum(total.ravel(), 1.0)  # 1 but for rounding
        return self._p_optimal


class FittedTwinSearcher(NewCellSearcher):
    """Proposes and recommends where the posterior over the worker's hypotheses puts the
    optimum; see the module.

    Args:
        grid, seed, prior: as every searcher's (the prior is needed: its location breaks ties
            and its slope centres the displacements).
        twins: the candidate twins.
    """

    name = "fitted-twin"

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None,
                 twins: TwinLibrary | None = None):
        if prior is None:
            raise ConfigError("searcher fitted-twin needs a worker's prior (a population "
                              "prior's location and SD)")
        if twins is None:
            raise ConfigError("searcher fitted-twin needs candidate twins (a TwinLibrary)")
        super().__init__(grid, seed, prior)
        self.twins = twins
        self.posterior = BodyPosterior(twins, prior)
        centre, _ = prior_point(grid, prior)
        index = np.indices(grid.shape).reshape(3, -1).T
        self.prior_distance = np.linalg.norm(index - centre, axis=1)
        """(grid.size,) each cell's distance from the prior's location [cells]: of cells the
        posterior holds equally probable, the nearest is proposed and recommended."""
        self._nearest = np.argsort(self.prior_distance, kind="stable")

    @property
    def chosen(self) -> int:
        """The candidate of highest posterior probability (its displacements summed)."""
        return int(np.argmax(self.posterior.candidate_weights()))

    def search(self, evaluations) -> dict:
        super().search(evaluations)
        return {"fitted_twin": self.twins.names[self.chosen]}

    def _ranked(self) -> np.ndarray:
        """Cells by the optimum's probability, highest first (equal: nearest the prior)."""
        p = self.posterior.p_optimal()
        held = np.flatnonzero(p > 0)  # few cells: sorted alone, then the rest by distance
        return np.concatenate([held[np.lexsort((self.prior_distance[held], -p[held]))],
                               self._nearest[p[self._nearest] == 0]])

    def recommend(self) -> Recommendation:
        cell = int(self._ranked()[0])
        return Recommendation(cell, float(self.posterior.p_optimal()[cell]))

    def _propose(self) -> int:
        for cell in self._ranked():
            if int(cell) not in self.told:
                return int(cell)
        raise ConfigError("searcher fitted-twin: every cell has been evaluated")

    def _learn(self, cell: int, score: float) -> None:
        self.posterior.update(cell, self.heard[cell])


def survey_library(evaluator: Evaluator, grid: Grid, objective: str, seed: int,
                   progress: bool = True, angle_sd_deg: float = 5.0,
                   error: ErrorModel | MeasuredError | None = None) -> TwinLibrary:
    """A worker's candidate twins for ``ergohandover personalise``: the twin the session was
    given, the same twin with each impairment (:data:`~..twin.joint_limits.IMPAIRMENTS`), and
    the :data:`CANDIDATES` bodies nearest its stature among :data:`SURVEY_DRAWS` drawn from the
    survey's body model for its sex (seeded), with its task and settings. A candidate's
    landscape is swept (or read from the cache) when first needed; the answers' angles are
    measured with ``error`` (else ``angle_sd_deg`` on each)."""
    from ..landscape.store import landscape_of
    from ..twin.anthropometry import BodySpec
    from ..twin.joint_limits import IMPAIRMENTS, impaired

    body = evaluator.body
    drawn = BodySpec.sample(SURVEY_DRAWS, body.sex, np.random.default_rng([seed, SURVEY_DRAWS]))
    near = sorted(drawn, key=lambda b: abs(b.stature_m - body.stature_m))[:CANDIDATES]
    own = [] if body.restrictions else [impaired(body, name) for name in IMPAIRMENTS]
    evaluators = [evaluator, *(dataclasses.replace(evaluator, body=b) for b in (*own, *near))]
    names = ["the given worker", *(f"the given worker, {name}" for name in IMPAIRMENTS
                                   if own),
             *(f"survey body {i + 1} ({b.stature_m:.3f} m)" for i, b in enumerate(near))]
    return TwinLibrary(grid, evaluators, lambda i: landscape_of(evaluators[i], grid,
                                                              progress=progress),
                       objective, names, worker=(body.stature_m, body.sex),
                       angle_sd_deg=angle_sd_deg, error=error)
