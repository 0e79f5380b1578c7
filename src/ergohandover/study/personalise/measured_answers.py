"""The personalisation study with answers as a site gets them, at equal budgets.

The main comparison (:mod:`.sessions`) answers every handover with the twin's exact score
and stops a run at the worker's known minimum: the ceiling. This one is what a site would see:

- **answers with error** (:class:`Answers`): the worker's posture *measured* with the
  robustness part's Gaussian error of SD σ on every angle and scored
  (:class:`~.measured.MeasuredScores`; σ = 0 is the exact answer), or the score given
  by a *rater* whose intra-rater reliability is a published ICC
  (:class:`~.measured.RatedScores`);
- **equal budgets**: nobody knows the worker's minimum; every searcher gets the same handovers,
  and what it recommends after B of them is read;
- **recommendation rules** (:data:`RULES`): a searcher with a model of the worker (the fitted
  twin, the preference GP: ``model`` in the registry) recommends where that model expects the
  worker's optimum (``model``: :meth:`recommend`, with the model's probability that it is the
  optimum), and may stop early (``model, stopped``: at the first handover after which that
  probability reaches the stopping level, ``stop_level``; the handovers used are reported). A
  searcher without one recommends from a model of the worker fitted to its answers
  (``model``: :func:`worker_model_recommendations`, the fitted twin's posterior over bodies
  weighed by every measured angle, or by the score alone: the tried location where it expects
  the lowest true score). Beside it, for comparison: the location of the lowest answer among B
  handovers (``lowest``, the first of equals: under measurement error it favours a lucky
  reading), and (``confirm``) searching B − k handovers and spending the last k
  (:func:`confirmations`) measuring the k best again, the lowest mean of two recommended — a
  repeat costs a handover;
- **a twin fitted to the worker** (:mod:`~...search.fitted_twin`): a posterior over the
  population's other bodies, displaced a little, weighed by every measured angle;
- **workers who are not the twin**: besides the population's workers (*in-model*: the prior was
  fitted to twins like the one that answers), the same workers with a modelling choice of the
  sensitivity study changed (gaze, effort, joint preferences: *out-of-model*), whose optimum the
  prior has never seen, and workers the prior does not know (:mod:`.unknown_workers`:
  *impaired*, or who step, or of other proportions);
- **the baseline**: handing over once at the prior's location and stopping (:func:`no_search`),
  what a site has without searching; every searcher's gain over it and harm (runs worse than
  it) are paired per worker.

What counts is the recommendation's **true regret**: the worker's error-free score there minus
their own optimum, and whether it is 0. The ``+prior`` searchers (and the prior alone) get the
worker's leave-one-out prior. A run's errors come from a stream of its own (its seed and the
answers' model), so runs are paired across searchers only in their seeds.
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd
from scipy import stats

from ...envs.scores import Answer, ScoreSource
from ...errors import ConfigError
from ...landscape.grid import Grid
from ...landscape.store import landscape_of
from ...robustness.measured_error import MEASURED_ERROR, MeasuredError
from ...robustness.posture_error import ANGLE_COLUMNS, ErrorModel
from ...search import Budget, entry, make
from ...search import run as run_search
from ...search.fitted_twin import BodyPosterior, TwinLibrary
from ...search.prior import Prior
from ...twin.evaluate import Evaluator
from .measured import MeasuredScores, RatedScores, rater_sd
from .sessions import success_interval, values_for
from .unknown_workers import IN_MODEL, OUT_OF_MODEL, group_of

KINDS = ("posture", "rater", "imu")
RULES = ("model", "model, stopped", "lowest", "confirm")
BLOCK = 3
"""A worker's postures are solved in aligned cubes of this edge [cells] on a miss: searchers
propose near where they proposed before, and the solver's cost is mostly per call."""


@dataclass(frozen=True)
class Answers:
    """How a handover is answered.

    Attributes:
        kind: ``posture`` (the posture measured with error, then scored), ``imu`` (measured
            as an IMU suit measures it: the robustness part's
            :data:`~...robustness.measured_error.MEASURED_ERROR`) or ``rater`` (a rater's
            score).
        level: the posture error's SD [deg], the factor on the IMU's SDs, or the rater's ICC
            (0, 1].
    """

    kind: str
    level: float

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ConfigError(f"answers = {self.kind!r} is not allowed (use {', '.join(KINDS)})")
        if self.kind == "rater" and not 0 < self.level <= 1:
            raise ConfigError(f"rater ICC = {self.level!r} is outside the valid range (0, 1]")
        if self.kind in ("posture", "imu") and not (math.isfinite(self.level)
                                                   and self.level >= 0):
            raise ConfigError(f"posture SD = {self.level!r} is outside the valid range (>= 0)")

    @property
    def label(self) -> str:
        if self.kind == "posture":
            return "exact" if self.level == 0 else f"posture SD {self.level:g} deg"
        if self.kind == "imu":
            return "IMU" + ("" if self.level == 1 else f" SDs x{self.level:g}")
        return f"rater ICC {self.level:g}"

    @property
    def error(self) -> ErrorModel | MeasuredError | None:
        """The posture's measurement error (None: a rater's score)."""
        if self.kind == "posture":
            return ErrorModel(self.level)
        return replace(MEASURED_ERROR, scale=self.level) if self.kind == "imu" else None

    def source(self, grid: Grid, evaluator: Evaluator, objective: str, values: np.ndarray,
               rng: np.random.Generator, postures: dict) -> ScoreSource:
        """The score source answering a run's handovers."""
        error = self.error  # a measured error model factors its covariance when made
        if error is not None:
            return MeasuredScores(grid, evaluator, objective, error, rng, block=BLOCK,
                                  postures=postures)
        return RatedScores(grid, values, rater_sd(values, self.level), rng, objective)


def angle_sds(answers: Answers) -> dict[str, float]:
    """Each angle's measurement SD under an answer model [deg] (0: a rater's score carries no
    angles). The fitted twin weighs each angle alone by it: an IMU's bias and correlations are
    left out of its likelihood."""
    error = answers.error
    if isinstance(error, MeasuredError):
        return dict(zip(ANGLE_COLUMNS, map(float, error.sd()), strict=True))
    return {c: 0.0 if error is None else error.sd_deg for c in ANGLE_COLUMNS}


def answer_models(sds: tuple[float, ...], iccs: tuple[float, ...],
                  imu: tuple[float, ...] = ()) -> list[Answers]:
    """The study's answer models: posture errors of each SD, an IMU suit's (its SDs times
    each factor), then raters of each ICC."""
    return [*(Answers("posture", float(s)) for s in sds), *(Answers("imu", float(s)) for s in imu),
            *(Answers("rater", float(i)) for i in iccs)]


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
        candidates: (name, evaluator) of the bodies a model of the worker chooses from (the
            population's other workers and their impaired twins): a fitted twin's, and every
            other searcher's recommendation (none: the lowest reading and confirm rules only).
        stop_level: the stopping rule's level: a run stops at the first handover after which
            its model's probability that the recommendation is the optimum reaches it.
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
    stop_level: float = 0.8


_POSTURES: dict[str, dict] = {}
"""Each worker's solved postures by cell, shared by every run on it in this process."""
_CANDIDATES: dict[tuple[str, str], np.ndarray] = {}
"""Candidate twins' scores and angles by (candidate, what), shared by every fitted twin here
(filled by the parent before the pool forks: :func:`candidate_library`)."""


def model_of(twin: str) -> str:
    """The group a worker's twin is reported in: :data:`IN_MODEL`, ``out-of-model`` (a
    sensitivity variant) or the group of a worker the prior does not know
    (:mod:`.unknown_workers`)."""
    return IN_MODEL if twin == IN_MODEL else group_of(twin) or OUT_OF_MODEL


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


def candidate_library(candidates: Sequence[tuple[str, Evaluator]], grid: Grid, objective: str,
                      **settings) -> TwinLibrary:
    """The candidates' library, their landscapes read from the cache once per process."""
    evaluators = [e for _, e in candidates]
    return TwinLibrary(grid, evaluators,
                       lambda i: landscape_of(evaluators[i], grid, progress=False), objective,
                       [n for n, _ in candidates], cache=_CANDIDATES, **settings)


class Heard(ScoreSource):
    """A score source that keeps every answer it gives, in order (cell, answer): what a model
    of the worker is fitted to after the search (repeated handovers included)."""

    def __init__(self, inner: ScoreSource):
        self.inner, self.grid, self.heard = inner, inner.grid, []
        self.objective = getattr(inner, "objective", "paper_postural")

    def answer(self, flat: int) -> Answer:
        found = self.inner.answer(flat)
        self.heard.append((int(flat), found))
        return found

    def score(self, flat: int) -> float:
        return self.answer(flat).score


def worker_model_recommendations(twins: TwinLibrary, prior: Prior,
                                 answers: list[tuple[int, Answer]],
                                 budgets: Sequence[int]) -> dict[int, int | None]:
    """For a searcher without a model of its own: after each budget of distinct handovers,
    the tried location where a model of the worker expects the lowest true score — the fitted
    twin's posterior over bodies (:class:`~...search.fitted_twin.BodyPosterior`), fitted to
    every answer heard so far (each measured angle, or the score alone); the first tried of
    equals; None while nothing feasible was heard."""
    posterior = BodyPosterior(twins, prior)
    tried: list[int] = []
    found: dict[int, int | None] = {}

    def recommend() -> int | None:
        feasible = [c for c in tried if c in fine]
        if not feasible:
            return None
        return feasible[int(np.argmin(np.round(posterior.expected_scores(feasible), 9)))]

    fine: set[int] = set()
    wanted = sorted(set(budgets))
    for cell, answer in answers:
        if cell not in tried:
            if len(tried) in wanted:  # the budget's answers are all in: before a new one
                found[len(tried)] = recommend()
            tried.append(cell)
        posterior.update(cell, answer)
        if math.isfinite(answer.score):
            fine.add(cell)
    for budget in wanted:  # a search that ended within the budget: its answers so far
        found.setdefault(budget, recommend())
    return found


def run_measured_job(job: MeasuredJob) -> list[dict]:
    """Every run of the job: one row per budget and rule (the recommendation, its answer and
    true score, its true regret)."""
    values = truth_of(job)
    lowest_score = float(values.min())
    postures = _POSTURES.setdefault(f"{truth_key(job.worker, job.twin)}|{job.grid.describe()}",
                                    {})
    prior = job.prior if entry(job.searcher).prior == "needs" else None

    def source(rng):
        return job.answers.source(job.grid, job.evaluator, job.objective, values, rng, postures)

    twins = None
    if job.candidates:
        body = job.evaluator.body
        twins = candidate_library(job.candidates, job.grid, job.objective,
                                  worker=(body.stature_m, body.sex),
                                  angle_sd_deg=angle_sds(job.answers), error=job.answers.error)
    rows = []
    largest = max(job.budgets)
    model = entry(job.searcher).model
    for run, seed in enumerate(job.seeds):
        heard = Heard(source(measurement_rng(seed, job.answers)))
        record = run_search(make(job.searcher, job.grid, seed, prior,
                                 twins=twins if entry(job.searcher).twins else None),
                            heard, Budget(evaluations=largest),
                            recommend_at=range(1, largest + 1) if model else ())
        worker_model = (worker_model_recommendations(twins, job.prior, heard.heard,
                                                     job.budgets)
                        if twins is not None and not model else {})
        kept = record.info.get("recommendations", {})  # handovers -> the model's, if it has one
        for budget in sorted(job.budgets):
            spent = min(budget, len(record.cells))
            found = {}
            if model:
                now = kept[spent]
                found["model"] = (now.cell, math.nan, spent, now.p_optimal)
                if not math.isnan(now.p_optimal):  # a model that states its probability
                    stop = next((n for n in range(1, spent + 1)
                                 if kept[n].p_optimal >= job.stop_level), spent)
                    found["model, stopped"] = (kept[stop].cell, math.nan, stop,
                                               kept[stop].p_optimal)
            else:  # a model of the worker's, and the lowest reading's beside it
                if budget in worker_model:
                    found["model"] = (worker_model[budget], math.nan, spent, math.nan)
                best = recommendation(record.scores, budget)
                again = source(measurement_rng(seed, job.answers, budget))
                lowest = None if best is None else record.cells[best]
                found["lowest"] = (lowest, math.nan if best is None else record.scores[best],
                                   spent, math.nan)
                index, answer, used = confirmed(record.cells, record.scores, budget,
                                                again.score)
                found["confirm"] = (None if index is None else record.cells[index], answer,
                                    used, math.nan)
            for rule, (cell, answer, used, p_optimal) in found.items():
                cell = -1 if cell is None else int(cell)
                true = math.inf if cell < 0 else float(values[cell])
                rows.append({"worker": job.worker, "twin": job.twin, "searcher": job.searcher,
                             "answers": job.answers.label, "rule": rule, "run": run,
                             "seed": seed, "budget": budget, "handovers": used, "cell": cell,
                             "answer": answer, "true_score": true, "optimum_score": lowest_score,
                             "regret": true - lowest_score, "p_optimal": p_optimal})
    return rows


def no_search(values: np.ndarray, grid: Grid, prior: Prior) -> float:
    """The true regret of handing over once at the prior's location and stopping: what a site
    gets without searching."""
    return float(values[grid.nearest_cell(prior.location)] - values.min())


def mean_interval(per_unit: np.ndarray, rng: np.random.Generator) -> tuple[float, float]:
    """A 95 % percentile bootstrap interval of the mean over units (the mean itself where the
    units agree or one is infinite)."""
    mean = float(per_unit.mean())
    if not (np.ptp(per_unit) > 0 and np.isfinite(per_unit).all()):
        return mean, mean
    found = stats.bootstrap((per_unit,), np.mean, n_resamples=2000, method="percentile",
                            random_state=rng).confidence_interval
    return float(found.low), float(found.high)


def measured_summary(runs: pd.DataFrame, baseline: pd.Series, seed: int) -> pd.DataFrame:
    """Per model (:func:`model_of`), searcher, answers, rule and budget: workers, runs, the
    share of runs whose recommendation is a true optimum (interval: bootstrap over workers, at
    least Wilson's), the mean true regret, the **gain over no search** (``baseline``: each
    worker's regret at the prior's location, :func:`no_search`; paired per worker, interval:
    bootstrap over workers) and the **harm** (share of runs worse than no search), the
    handovers used and the model's mean stated probability. Out of model, a worker is a worker
    with one changed twin; the "no search" rows are the baseline itself. Each row's intervals
    draw from a generator of its own (the seed and the row's key), so a row's interval does not
    move when another row's runs change."""
    runs = runs.assign(model=runs["twin"].map(model_of),
                       unit=runs["worker"] + "|" + runs["twin"])
    runs["baseline"] = runs["unit"].map(baseline)
    keys = ["model", "searcher", "answers", "rule", "budget"]
    first = runs.drop_duplicates(["model", "answers", "unit"]).assign(
        searcher="no search", rule="prior's location", budget=1, handovers=1,
        regret=lambda t: t["baseline"], p_optimal=np.nan)
    rows = []
    for key, table in pd.concat([first, runs], ignore_index=True).groupby(keys, sort=False):
        rng = np.random.default_rng([seed, zlib.crc32("|".join(map(str, key)).encode())])
        units = table["unit"].to_numpy()
        zero = (table["regret"] == 0).to_numpy()
        per_worker = pd.Series(zero).groupby(units).mean().to_numpy()
        low, high = success_interval(per_worker, int(zero.sum()), len(zero), rng)
        regret = table.groupby("unit")["regret"].mean().to_numpy()
        r_low, r_high = mean_interval(regret, rng)
        gain = (table["baseline"] - table["regret"]).groupby(units).mean().to_numpy()
        g_low, g_high = mean_interval(gain, rng)
        worse = (table["regret"] > table["baseline"]).to_numpy()
        per_harm = pd.Series(worse).groupby(units).mean().to_numpy()
        h_low, h_high = success_interval(per_harm, int(worse.sum()), len(worse), rng)
        rows.append({**dict(zip(keys, key, strict=True)),
                     "n_workers": len(per_worker), "n_runs": len(table),
                     "p_regret_0": float(zero.mean()), "ci_low": low, "ci_high": high,
                     "mean_regret": float(regret.mean()), "regret_ci_low": r_low,
                     "regret_ci_high": r_high, "gain": float(gain.mean()),
                     "gain_ci_low": g_low, "gain_ci_high": g_high, "harm": float(worse.mean()),
                     "harm_ci_low": h_low, "harm_ci_high": h_high,
                     "mean_handovers": float(table["handovers"].mean()),
                     "model_p_optimal": float(table["p_optimal"].mean())})
    return pd.DataFrame(rows)
