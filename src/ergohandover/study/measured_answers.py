"""The personalisation study with answers as a site measures them.

The main comparison (:mod:`.personalise`) answers every handover with the twin's exact score
and stops a run at the worker's known minimum. This one is what a site would see:

- every handover is answered with the worker's posture *measured* with error, each angle
  carrying the robustness part's Gaussian error of SD σ (:class:`~..search.measured.
  MeasuredScores`), and scored; σ = 0 is the exact answer, the ceiling;
- every searcher gets the same budgets and no stop rule: nobody knows the worker's minimum;
- after B handovers the recommendation is the location of the lowest *measured* score (the
  first of equals), and what counts is its **true regret**: the worker's error-free score
  there minus their own optimum, and whether it is 0.

Searchers that take a prior get the worker's leave-one-out prior. A run's measurement errors
come from a stream of its own (its seed and σ), so runs are paired across searchers at one σ
only in their seeds, not in their errors. Results: ``measured_runs.csv`` (a row per worker,
searcher, σ, run and budget) and ``measured_summary.csv`` (per searcher, σ and budget).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from ..landscape.grid import Grid
from ..robustness.posture_error import ErrorModel
from ..search import Budget, entry, make
from ..search import run as run_search
from ..search.measured import MeasuredScores
from ..search.prior import Prior
from ..twin.evaluate import Evaluator
from .personalise import success_interval, values_of


@dataclass(frozen=True)
class MeasuredJob:
    """Every run of one searcher on one worker at one measurement error.

    Attributes:
        worker, evaluator, grid, objective, prior: as :class:`~.personalise.PersonaliseJob`'s.
        searcher: a searcher of the registry (given the prior if it takes one).
        sd: the measurement error's SD [deg].
        budgets: handovers after which the recommendation is read (the largest is run).
        seeds: one seed per run (the main comparison's: the same searcher proposals at σ 0).
    """

    worker: str
    evaluator: Evaluator
    grid: Grid
    objective: str
    searcher: str
    sd: float
    budgets: tuple[int, ...]
    seeds: tuple[int, ...]
    prior: Prior


_POSTURES: dict[str, dict] = {}
"""Each worker's solved postures by cell, shared by every run on it in this process."""


def measurement_rng(seed: int, sd: float) -> np.random.Generator:
    """A run's stream of measurement errors, from its seed and σ alone."""
    return np.random.default_rng([seed, round(1000 * sd), 1 << 16])


def recommendation(scores: list[float], budget: int) -> int | None:
    """The index of the lowest finite score among the first ``budget`` (the first of equals),
    or None if none of them was feasible."""
    seen = np.asarray(scores[:budget], dtype=float)
    if not np.isfinite(seen).any():
        return None
    return int(np.argmin(seen))


def run_measured_job(job: MeasuredJob) -> list[dict]:
    """Every run of the job: one row per budget (the recommendation, its measured and true
    score, its true regret)."""
    values = values_of(job)
    lowest = float(values.min())
    postures = _POSTURES.setdefault(f"{job.worker}|{job.grid.describe()}", {})
    prior = None if entry(job.searcher).prior == "none" else job.prior
    rows = []
    for run, seed in enumerate(job.seeds):
        source = MeasuredScores(job.grid, job.evaluator, job.objective, ErrorModel(job.sd),
                                measurement_rng(seed, job.sd), postures=postures)
        record = run_search(make(job.searcher, job.grid, seed, prior), source,
                            Budget(evaluations=max(job.budgets)))
        for budget in sorted(job.budgets):
            best = recommendation(record.scores, budget)
            cell = None if best is None else record.cells[best]
            true = math.inf if cell is None else float(values[cell])
            x, y, z = (math.nan,) * 3 if cell is None else job.grid.point(cell)
            rows.append({"worker": job.worker, "searcher": job.searcher, "sd_deg": job.sd,
                         "run": run, "seed": seed, "budget": budget,
                         "handovers": min(budget, len(record.cells)),
                         "measured_score": math.nan if best is None else record.scores[best],
                         "true_score": true, "optimum_score": lowest,
                         "regret": true - lowest, "x": round(float(x), 6),
                         "y": round(float(y), 6), "z": round(float(z), 6)})
    return rows


def measured_summary(runs: pd.DataFrame, seed: int) -> pd.DataFrame:
    """Per searcher, σ and budget: workers, runs, the share of runs whose recommendation is a
    true optimum (interval: bootstrap over workers, at least Wilson's) and the mean true regret
    (interval: percentile bootstrap over the workers' means)."""
    rng = np.random.default_rng(seed)
    rows = []
    for (searcher, sd, budget), table in runs.groupby(["searcher", "sd_deg", "budget"],
                                                      sort=False):
        zero = (table["regret"] == 0).to_numpy()
        per_worker = pd.Series(zero).groupby(table["worker"].to_numpy()).mean().to_numpy()
        low, high = success_interval(per_worker, int(zero.sum()), len(zero), rng)
        regret = table.groupby("worker")["regret"].mean().to_numpy()
        r_low = r_high = float(regret.mean())
        if np.ptp(regret) > 0 and np.isfinite(regret).all():
            interval = stats.bootstrap((regret,), np.mean, n_resamples=2000,
                                       method="percentile", random_state=rng)
            r_low, r_high = (float(interval.confidence_interval.low),
                             float(interval.confidence_interval.high))
        rows.append({"searcher": searcher, "sd_deg": sd, "budget": budget,
                     "n_workers": table["worker"].nunique(), "n_runs": len(table),
                     "p_regret_0": float(zero.mean()), "ci_low": low, "ci_high": high,
                     "mean_regret": float(regret.mean()), "regret_ci_low": r_low,
                     "regret_ci_high": r_high})
    return pd.DataFrame(rows)
