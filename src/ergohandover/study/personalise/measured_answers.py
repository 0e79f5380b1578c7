"""The personalisation study with answers as a site gets them, at equal budgets.

The main comparison (:mod:`.sessions`) answers every handover with the twin's exact score
and stops a run at the worker's known minimum: the ceiling. This one is what a site would see:

- **answers with error** (:class:`Answers`): the worker's posture *measured* with the
  robustness part's Gaussian error of SD σ on every angle and scored
  (:class:`~.measured.MeasuredScores`; σ = 0 is the exact answer), or the score given
  by a *rater* whose intra-rater reliability is a published ICC
  (:class:`~.measured.RatedScores`);
- **equal budgets and no stop rule**: nobody knows the worker's minimum; every searcher gets the
  same handovers, and what it recommends after B of them is read from what was observed;
- **recommendation rules** (:data:`RULES`): ``lowest``, the location of the lowest answer
  among B handovers (the first of equals); ``confirm``, B − k handovers searched and the last
  k (:func:`confirmations`) spent measuring the k best locations again, the lowest mean of two
  answers recommended — a repeat at a location costs a handover, as it is a new measurement;
  ``preferred``, for a searcher told only which of the last two handovers was better
  (:mod:`~...search.pairwise`: the answers' scores compared), the location its own model
  prefers;
- **a twin fitted to the worker** (:mod:`~...search.fitted_twin`): after the prior's first
  handovers, the population's other body whose twin explains them best, its optimum proposed;
- **workers who are not the twin**: besides the population's workers (*in-model*: the prior was
  fitted to twins like the one that answers), the same workers with a modelling choice of the
  sensitivity study changed (gaze, effort, joint preferences: *out-of-model*), whose optimum the
  prior has never seen.

What counts is the recommendation's **true regret**: the worker's error-free score there minus
their own optimum, and whether it is 0. The ``+prior`` searchers (and the prior alone) get the
worker's leave-one-out prior. A run's errors come from a stream of its own (its seed and the
answers' model), so runs are paired across searchers only in their seeds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from ...envs.scores import ScoreSource
from ...errors import ConfigError
from ...landscape.grid import Grid
from ...robustness.posture_error import ErrorModel
from ...search import Budget, entry, make
from ...search import run as run_search
from ...search.fitted_twin import TwinLibrary
from ...search.pairwise import preferred
from ...search.prior import Prior
from ...twin.evaluate import Evaluator
from .measured import MeasuredScores, RatedScores, rater_sd
from .sessions import success_interval, values_for

KINDS = ("posture", "rater")
RULES = ("lowest", "confirm", "preferred")
IN_MODEL = "in-model"


@dataclass(frozen=True)
class Answers:
    """How a handover is answered.

    Attributes:
        kind: ``posture`` (the posture measured with error, then scored) or ``rater`` (a
            rater's score).
        level: the posture error's SD [deg], or the rater's ICC (0, 1].
    """

    kind: str
    level: float

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ConfigError(f"answers = {self.kind!r} is not allowed (use {', '.join(KINDS)})")
        if self.kind == "rater" and not 0 < self.level <= 1:
            raise ConfigError(f"rater ICC = {self.level!r} is outside the valid range (0, 1]")
        if self.kind == "posture" and not (math.isfinite(self.level) and self.level >= 0):
            raise ConfigError(f"posture SD = {self.level!r} is outside the valid range (>= 0)")

    @property
    def label(self) -> str:
        if self.kind == "posture":
            return "exact" if self.level == 0 else f"posture SD {self.level:g} deg"
        return f"rater ICC {self.level:g}"

    def source(self, grid: Grid, evaluator: Evaluator, objective: str, values: np.ndarray,
               rng: np.random.Generator, postures: dict) -> ScoreSource:
        """The score source answering a run's handovers."""
        if self.kind == "posture":
            return MeasuredScores(grid, evaluator, objective, ErrorModel(self.level), rng,
                                  postures=postures)
        return RatedScores(grid, values, rater_sd(values, self.level), rng, objective)


def answer_models(sds: tuple[float, ...], iccs: tuple[float, ...]) -> list[Answers]:
    """The study's answer models: posture errors of each SD, then raters of each ICC."""
    return [Answers("posture", float(s)) for s in sds] + [Answers("rater", float(i))
                                                          for i in iccs]


@dataclass(frozen=True)
class MeasuredJob:
    """Every run of one searcher on one worker under one answer model.

    Attributes:
        worker: the worker's id; ``twin``: :data:`IN_MODEL` or the sensitivity variant its
            twin differs by; ``evaluator``: that twin (who answers).
        grid, objective, prior: as :class:`~.sessions.PersonaliseJob`'s.
        searcher: a searcher of the registry (given the prior if it needs one: the ``+prior``
            entries).
        answers: how each handover is answered.
        budgets: handovers after which the recommendation is read (the largest is run).
        seeds: one seed per run.
        candidates: (name, evaluator) of the bodies a fitted twin chooses from (the
            population's other workers; only for a searcher that needs them).
    """

    worker: str
    twin: str
    evaluator: Evaluator
    grid: Grid
    objective: str
    searcher: str
    answers: Answers
    budgets: tuple[int, ...]
    seeds: tuple[int, ...]
    prior: Prior
    candidates: tuple[tuple[str, Evaluator], ...] = ()


_POSTURES: dict[str, dict] = {}
"""Each worker's solved postures by cell, shared by every run on it in this process."""
_ANGLES: dict[tuple[str, int], np.ndarray] = {}
"""Candidate twins' solved angles by (candidate, cell), shared by every fitted twin here."""


def truth_key(worker: str, twin: str) -> str:
    """The name a worker's true scores are kept under (:func:`~.sessions.prepare_values`)."""
    return worker if twin == IN_MODEL else f"{worker}|{twin}"


def truth_of(job: MeasuredJob) -> np.ndarray:
    """The job's worker's error-free objective at every cell (the parent's, if it has it)."""
    return values_for(truth_key(job.worker, job.twin), job.evaluator, job.grid, job.objective)


def measurement_rng(seed: int, answers: Answers, stream: int = 0) -> np.random.Generator:
    """A run's errors, from its seed, the answer model and the stream alone (0: the search's
    answers; B: the confirmations at budget B)."""
    return np.random.default_rng([seed, KINDS.index(answers.kind), round(1000 * answers.level),
                                  stream, 1 << 16])


def recommendation(scores: list[float], budget: int) -> int | None:
    """The index of the lowest finite score among the first ``budget`` (the first of equals),
    or None if none of them was feasible."""
    seen = np.asarray(scores[:budget], dtype=float)
    if not np.isfinite(seen).any():
        return None
    return int(np.argmin(seen))


def confirmations(budget: int) -> int:
    """Handovers the ``confirm`` rule spends measuring again at a budget: a fifth, at least 1."""
    return max(1, budget // 5)


def confirmed(cells: list[int], scores: list[float], budget: int,
              measure_again) -> tuple[int | None, float, int]:
    """The ``confirm`` rule: the first ``budget - k`` answers searched, the k lowest of them
    (:func:`confirmations`; the first of equals) measured once more with ``measure_again(cell)``,
    the lowest mean of two recommended. Returns its index (None: nothing feasible), its mean
    answer and the handovers spent."""
    if budget < 2:
        raise ConfigError(f"budget = {budget} is outside the valid range for confirming (at "
                          "least 2: one handover to search, one to measure again)")
    k = confirmations(budget)
    seen = np.asarray(scores[:budget - k], dtype=float)
    feasible = np.flatnonzero(np.isfinite(seen))
    if feasible.size == 0:
        return None, math.nan, len(seen)
    candidates = feasible[np.argsort(seen[feasible], kind="stable")[:k]]
    means = np.array([(seen[i] + measure_again(cells[i])) / 2 for i in candidates])
    best = int(np.argmin(means))
    return int(candidates[best]), float(means[best]), len(seen) + len(candidates)


def run_measured_job(job: MeasuredJob) -> list[dict]:
    """Every run of the job: one row per budget and rule (the recommendation, its answer and
    true score, its true regret)."""
    values = truth_of(job)
    lowest = float(values.min())
    postures = _POSTURES.setdefault(f"{truth_key(job.worker, job.twin)}|{job.grid.describe()}",
                                    {})
    prior = job.prior if entry(job.searcher).prior == "needs" else None

    def source(rng):
        return job.answers.source(job.grid, job.evaluator, job.objective, values, rng, postures)

    twins = None
    if entry(job.searcher).twins:
        names = [n for n, _ in job.candidates]
        evaluators = [e for _, e in job.candidates]
        twins = TwinLibrary(job.grid, evaluators, lambda i: values_for(
            names[i], evaluators[i], job.grid, job.objective), names, cache=_ANGLES)
    rows = []
    for run, seed in enumerate(job.seeds):
        record = run_search(make(job.searcher, job.grid, seed, prior, twins=twins),
                            source(measurement_rng(seed, job.answers)),
                            Budget(evaluations=max(job.budgets)))
        for budget in sorted(job.budgets):
            spent = min(budget, len(record.cells))
            if entry(job.searcher).answers == "preferences":
                found = {"preferred": (preferred(job.grid, record.cells[:budget],
                                                 record.scores[:budget]), math.nan, spent)}
            else:
                best = recommendation(record.scores, budget)
                again = source(measurement_rng(seed, job.answers, budget))
                found = {"lowest": (best, math.nan if best is None else record.scores[best],
                                    spent),
                         "confirm": confirmed(record.cells, record.scores, budget,
                                              again.score)}
            for rule in found:
                index, answer, spent = found[rule]
                cell = -1 if index is None else record.cells[index]
                true = math.inf if index is None else float(values[cell])
                rows.append({"worker": job.worker, "twin": job.twin, "searcher": job.searcher,
                             "answers": job.answers.label, "rule": rule, "run": run,
                             "seed": seed, "budget": budget, "handovers": spent, "cell": cell,
                             "answer": answer, "true_score": true, "optimum_score": lowest,
                             "regret": true - lowest})
    return rows


def measured_summary(runs: pd.DataFrame, seed: int) -> pd.DataFrame:
    """Per model (in- or out-of-model), searcher, answers, rule and budget: workers, runs, the
    share of runs whose recommendation is a true optimum (interval: bootstrap over workers, at
    least Wilson's) and the mean true regret (interval: percentile bootstrap over the workers'
    means). Out of model, a worker is a worker with one changed twin."""
    rng = np.random.default_rng(seed)
    runs = runs.assign(model=np.where(runs["twin"] == IN_MODEL, IN_MODEL, "out-of-model"),
                       unit=runs["worker"] + "|" + runs["twin"])
    rows = []
    for key, table in runs.groupby(["model", "searcher", "answers", "rule", "budget"],
                                   sort=False):
        zero = (table["regret"] == 0).to_numpy()
        units = table["unit"].to_numpy()
        per_worker = pd.Series(zero).groupby(units).mean().to_numpy()
        low, high = success_interval(per_worker, int(zero.sum()), len(zero), rng)
        regret = table.groupby("unit")["regret"].mean().to_numpy()
        r_low = r_high = float(regret.mean())
        if np.ptp(regret) > 0 and np.isfinite(regret).all():
            interval = stats.bootstrap((regret,), np.mean, n_resamples=2000,
                                       method="percentile", random_state=rng)
            r_low, r_high = (float(interval.confidence_interval.low),
                             float(interval.confidence_interval.high))
        rows.append({**dict(zip(["model", "searcher", "answers", "rule", "budget"], key,
                                strict=True)),
                     "n_workers": len(per_worker), "n_runs": len(table),
                     "p_regret_0": float(zero.mean()), "ci_low": low, "ci_high": high,
                     "mean_regret": float(regret.mean()), "regret_ci_low": r_low,
                     "regret_ci_high": r_high})
    return pd.DataFrame(rows)
