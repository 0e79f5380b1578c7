"""The personalisation study's logic: how many real handovers does each searcher need to find
one worker's own optimum?

Every worker of the population study has a landscape (the twin's score at every cell of the
population's grid); there the twin stands in for the person, and each evaluation stands for one
real handover. For each worker, searcher and run, the searcher is driven until it evaluates a
cell at the worker's own minimum of the objective (*the optimum*) or spends the largest budget.
On the way, the first evaluation within one point of that minimum is recorded too. Because no
searcher's proposals depend on its budget, one run at the largest budget answers every smaller
budget: a run succeeds at budget B when it reached the target within B evaluations.

Runs are paired: run r of a worker has the same seed for every searcher. The population prior
(:mod:`~ergohandover.search.prior`) of a worker is fitted to the other workers of the
population study (leave-one-out), so no worker's own optimum informs its prior.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from ...envs.scores import ArrayScores, objective_values
from ...landscape.grid import Grid
from ...landscape.store import landscape_of
from ...search import Budget, Record, entry, make
from ...search import run as run_search
from ...search.prior import PopulationPrior, Prior
from ...search.statistics import censored_median, wilson
from ...twin.evaluate import Evaluator

TARGETS = ("optimum", "within_1")


@dataclass(frozen=True)
class PersonaliseJob:
    """Every run of one searcher on one worker.

    Attributes:
        worker: the worker's id; ``evaluator`` and ``grid`` its landscape (read from the
            landscape cache, once per process).
        objective: what the searcher minimises.
        searcher: a searcher of the registry (those that need a prior get the worker's).
        budget: the largest budget [evaluations].
        seeds: one seed per run (the same for every searcher: paired runs).
        prior: the worker's leave-one-out population prior.
    """

    worker: str
    evaluator: Evaluator
    grid: Grid
    objective: str
    searcher: str
    budget: int
    seeds: tuple[int, ...]
    prior: Prior


def run_seeds(seed: int, worker: str, runs: int) -> tuple[int, ...]:
    """The seeds of a worker's runs, from the study's seed and the worker's name only."""
    sequence = np.random.SeedSequence([seed, zlib.crc32(worker.encode())])
    return tuple(int(s.generate_state(1)[0]) for s in sequence.spawn(runs))


_VALUES: dict[str, np.ndarray] = {}
"""Each worker's objective at every cell: filled by the parent (:func:`prepare_values`) before
the pool forks, so that its workers inherit them."""


def values_key(worker: str, objective: str, grid: Grid) -> str:
    return f"{worker}|{objective}|{grid.describe()}"


def prepare_values(worker: str, objective: str, landscape) -> np.ndarray:
    """A worker's objective at every cell (``inf`` where infeasible), kept for every job on it
    in this process and in the workers forked after."""
    key = values_key(worker, objective, landscape.grid)
    if key not in _VALUES:
        _VALUES[key] = objective_values(landscape, objective)
    return _VALUES[key]


def values_for(worker: str, evaluator: Evaluator, grid: Grid, objective: str) -> np.ndarray:
    """A worker's objective at every cell: the parent's (:func:`prepare_values`), or read
    through the landscape door in a process that has none."""
    found = _VALUES.get(values_key(worker, objective, grid))
    if found is not None:
        return found
    return prepare_values(worker, objective, landscape_of(evaluator, grid, progress=False))


def values_of(job: PersonaliseJob) -> np.ndarray:
    """The job's worker's objective (:func:`values_for`)."""
    return values_for(job.worker, job.evaluator, job.grid, job.objective)


def search_once(job: PersonaliseJob, values: np.ndarray, seed: int) -> Record:
    """One run: the searcher against the worker's landscape, stopped at the optimum; the
    worker's prior goes to a searcher that needs one (the others run without)."""
    prior = job.prior if entry(job.searcher).prior == "needs" else None
    searcher = make(job.searcher, job.grid, seed, prior)
    scores = ArrayScores(job.grid, values, job.objective)
    budget = Budget(evaluations=job.budget, stop_score=float(values.min()))
    return run_search(searcher, scores, budget)


def run_personalise_job(job: PersonaliseJob) -> list[dict]:
    """Every run of the job: one row each (evaluations to the optimum and to within one point
    of it, NaN where not reached; the best score and where)."""
    values = values_of(job)
    lowest = float(values.min())
    rows = []
    for run, seed in enumerate(job.seeds):
        record = search_once(job, values, seed)
        to_optimum, to_within = record.reached_at(lowest), record.reached_at(lowest + 1)
        cell, best = record.best or (-1, math.inf)
        x, y, z = job.grid.point(cell) if cell >= 0 else (math.nan,) * 3
        rows.append({"worker": job.worker, "searcher": job.searcher, "run": run, "seed": seed,
                     "optimum_score": lowest,
                     "evals_to_optimum": math.nan if to_optimum is None else to_optimum,
                     "evals_to_within_1": math.nan if to_within is None else to_within,
                     "evaluations": record.steps, "best_score": best,
                     "best_x": round(float(x), 6), "best_y": round(float(y), 6),
                     "best_z": round(float(z), 6)})
    return rows


def leave_one_out_priors(workers: pd.DataFrame, objective: str) -> dict[str, Prior]:
    """Each worker's prior from a model fitted to every other worker."""
    priors = {}
    for _, row in workers.iterrows():
        model = PopulationPrior.fit(workers[workers["worker"] != row["worker"]], objective)
        priors[row["worker"]] = model.predict(float(row["stature_m"]), row["sex"])
    return priors


def censored_at(evaluations: np.ndarray, budget: int) -> float:
    """Median evaluations to a target at ``budget``: a run that needed more counts as never
    reached (:func:`~ergohandover.search.statistics.censored_median`'s rule)."""
    return censored_median(np.where(evaluations > budget, np.nan, evaluations))


def success_interval(per_worker: np.ndarray, successes: int, runs: int,
                     rng: np.random.Generator) -> tuple[float, float]:
    """A 95 % interval for the share of successful runs: the percentile bootstrap over workers
    (runs of one worker are not independent: its landscape is shared), widened to at least the
    Wilson interval of the runs (when every worker's share is the same, the bootstrap has no
    spread, yet a finite number of runs still leaves the share uncertain)."""
    low, high = wilson(successes, runs)
    if np.ptp(per_worker) > 0:
        boot = stats.bootstrap((per_worker,), np.mean, n_resamples=2000, method="percentile",
                               random_state=rng).confidence_interval
        low, high = min(low, float(boot.low)), max(high, float(boot.high))
    return low, high


def summary(runs: pd.DataFrame, budgets: dict[str, list[int]], seed: int) -> pd.DataFrame:
    """Per searcher, target and budget: workers, runs, the share of runs that reached the
    target within the budget with its interval, and the median evaluations to the optimum and
    to within one point of it (censored at the budget)."""
    rows = []
    rng = np.random.default_rng(seed)
    for searcher, table in runs.groupby("searcher", sort=False):
        for target in TARGETS:
            evals = table[f"evals_to_{target}"].to_numpy(float)
            for budget in budgets[searcher]:
                hit = ~np.isnan(evals) & (evals <= budget)
                per_worker = pd.Series(hit).groupby(table["worker"].to_numpy()).mean().to_numpy()
                low, high = success_interval(per_worker, int(hit.sum()), len(hit), rng)
                rows.append({
                    "searcher": searcher, "target": target, "budget": budget,
                    "n_workers": table["worker"].nunique(), "n_runs": len(table),
                    "successes": int(hit.sum()), "success_rate": float(hit.mean()),
                    "ci_low": low, "ci_high": high,
                    "median_evals_to_optimum": censored_at(
                        table["evals_to_optimum"].to_numpy(float), budget),
                    "median_evals_to_within_1": censored_at(
                        table["evals_to_within_1"].to_numpy(float), budget)})
    return pd.DataFrame(rows)


def success_curves(runs: pd.DataFrame, largest: dict[str, int]) -> pd.DataFrame:
    """Share of runs that reached each target within n evaluations, n = 1 … the searcher's
    largest budget (the figure's curves)."""
    frames = []
    for searcher, table in runs.groupby("searcher", sort=False):
        at = np.unique(np.geomspace(1, largest[searcher], 200).round().astype(int))
        for target in TARGETS:
            evals = np.sort(table[f"evals_to_{target}"].to_numpy(float))
            reached = np.searchsorted(evals, at, side="right") / len(evals)  # NaN sorts last
            frames.append(pd.DataFrame({"searcher": searcher, "target": target,
                                        "evaluations": at, "success_rate": reached}))
    return pd.concat(frames, ignore_index=True)
