"""Compare the hand-written pairwise searcher with BoTorch's PairwiseGP + EUBO, side by side.

Usage: python experiments/tools/compare_pairwise.py [--workers N] [--runs R] [--budgets B ...]
       [--seed S] [--searchers NAME ...] [--jobs J]

On the personalisation study's own workers (the population's first N sampled workers, in
model), each with its leave-one-out prior, answered as the study answers the pairwise searcher
with error (exact answers, postures measured with 5° of error, a novice rater of ICC 0.51:
``measured_answers.Answers``, their errors drawn from the run's seed as the study draws them),
every searcher is started at the prior and told preferences (``pairwise+prior``). Run r of a
worker has one seed for every searcher (the study's ``run_seeds``), so runs are paired by
worker, seed and answer model. After each budget the searcher's recommendation (its model's:
``recommend()``) is read, and the study's summary (``measured_summary``: P(true optimum), mean
true regret, gain over no search — one handover at the prior's location — and harm, each with
its 95 % interval over workers) is printed, then each BoTorch searcher's paired difference from
the hand-written one (mean over workers of the per-worker mean difference; percentile bootstrap
over workers). Nothing is written to ``results/``. The landscapes come from the cache (swept if
missing).

Searchers: ``pairwise`` (search/pairwise.py), ``botorch`` (search/pairwise_botorch.py, kernel
fitted), ``botorch-fixed`` (the same with the hand-written searcher's fixed kernel).
"""

from __future__ import annotations

import argparse
import itertools
import math
import multiprocessing
import os
import time
from pathlib import Path

import numpy as np
import pandas as pd
from threadpoolctl import threadpool_limits

from ergohandover.search import Budget
from ergohandover.search import run as run_search
from ergohandover.search.pairwise import PairwiseSearcher
from ergohandover.search.pairwise_botorch import BotorchPairwiseSearcher
from ergohandover.study.config import StudyConfig
from ergohandover.study.personalise.measured_answers import (
    IN_MODEL,
    Answers,
    MeasuredJob,
    mean_interval,
    measured_summary,
    measurement_rng,
    no_search,
    truth_of,
)
from ergohandover.study.personalise.sessions import leave_one_out_priors, run_seeds, values_for
from ergohandover.study.shared import grid_of
from ergohandover.study.workforce import bodies
from ergohandover.twin.evaluate import Evaluator

SEARCHERS = {"pairwise": lambda g, s, p: PairwiseSearcher(g, s, p),
             "botorch": lambda g, s, p: BotorchPairwiseSearcher(g, s, p, fit=True),
             "botorch-fixed": lambda g, s, p: BotorchPairwiseSearcher(g, s, p, fit=False)}
ANSWERS = (Answers("posture", 0.0), Answers("posture", 5.0), Answers("rater", 0.51))
_POSTURES: dict[str, dict] = {}
"""Each worker's solved postures by cell, shared by every run on it in this process."""


def one_seed(task: tuple) -> list[dict]:
    """Every searcher's run on one worker, answer model and seed: a row per budget."""
    job, seed, searchers = task
    import torch

    torch.set_num_threads(1)  # one thread a process (BLAS too, below): the pool uses the cores
    with threadpool_limits(1):
        return seed_rows(job, seed, searchers)


def seed_rows(job: MeasuredJob, seed: int, searchers: tuple[str, ...]) -> list[dict]:
    """:func:`one_seed`'s rows."""
    values = truth_of(job)
    postures = _POSTURES.setdefault(job.worker, {})
    rows = []
    for name in searchers:
        source = job.answers.source(job.grid, job.evaluator, job.objective, values,
                                    measurement_rng(seed, job.answers), postures)
        started = time.perf_counter()
        searcher = SEARCHERS[name](job.grid, seed, job.prior)
        record = run_search(searcher, source,
                            Budget(evaluations=max(job.budgets)),
                            recommend_at=range(1, max(job.budgets) + 1))
        seconds = time.perf_counter() - started
        kept = record.info["recommendations"]
        for budget in job.budgets:
            spent = min(budget, len(record.cells))
            cell = kept[spent].cell
            true = math.inf if cell is None else float(values[cell])
            rows.append({"worker": job.worker, "twin": job.twin, "searcher": name,
                         "answers": job.answers.label, "rule": "model", "run": seed,
                         "seed": seed, "budget": budget, "handovers": spent,
                         "cell": -1 if cell is None else int(cell),
                         "regret": true - float(values.min()), "p_optimal": math.nan,
                         "seconds": seconds, "fits": getattr(searcher, "fits", 0),
                         "failed_fits": getattr(searcher, "failed_fits", 0)})
    return rows


def paired(runs: pd.DataFrame, base: str, other: str, seed: int) -> pd.DataFrame:
    """``other`` − ``base`` per answer model and budget, paired by worker and seed: the share
    of runs at a true optimum and the mean true regret, each averaged per worker first; 95 %
    percentile bootstrap over workers (the study's ``mean_interval``)."""
    rng = np.random.default_rng(seed)
    keys = ["answers", "budget", "worker", "seed"]
    wide = runs.pivot_table(index=keys, columns="searcher", values="regret", aggfunc="first")
    wide = wide.reset_index()
    rows = []
    for (answers, budget), table in wide.groupby(["answers", "budget"], sort=False):
        hit = ((table[other] == 0).astype(float) - (table[base] == 0).astype(float))
        regret = table[other] - table[base]
        by = table["worker"].to_numpy()
        row = {"answers": answers, "budget": budget, "n_workers": table["worker"].nunique(),
               "n_runs": len(table)}
        for name, diff in (("p_optimum", hit), ("regret", regret)):
            per_worker = diff.groupby(by).mean().to_numpy()
            low, high = mean_interval(per_worker, rng)
            row |= {f"d_{name}": per_worker.mean(), f"d_{name}_low": low,
                    f"d_{name}_high": high}
        rows.append(row)
    return pd.DataFrame(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=20, help="the study's first N workers "
                        "(default 20 of its 30: BoTorch's fitted kernel costs ~30 s a run)")
    parser.add_argument("--runs", type=int, default=1, help="runs per worker and answer model "
                        "(default 1)")
    parser.add_argument("--budgets", type=int, nargs="+", default=[10, 25],
                        help="handovers after which the recommendation is read (default 10 25)")
    parser.add_argument("--seed", type=int, default=28, help="the runs' seed (default 28, the "
                        "study's)")
    parser.add_argument("--searchers", nargs="+", default=list(SEARCHERS),
                        choices=tuple(SEARCHERS), help="the first is the base of the paired "
                        "differences (default: all three)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="processes (default: the cores)")
    args = parser.parse_args()
    config = StudyConfig()
    part = config.personalise
    table = config.population.workers()
    population = pd.read_csv(Path("results/population/workers.csv"))
    evaluators = [Evaluator(b, config.task()) for b in bodies(table)]
    grid = grid_of(evaluators[-1], config.population.boundary, config.population.step)
    chosen = [(w, e) for w, e, r in zip(table["worker"], evaluators, table["reference"],
                                        strict=True) if r == 0][:args.workers]
    priors = leave_one_out_priors(population[population["reference"] == 0], part.objective)
    jobs = [MeasuredJob(w, IN_MODEL, e, grid, part.objective, "pairwise+prior", answers,
                        tuple(sorted(args.budgets)), run_seeds(args.seed, w, args.runs),
                        priors[w]) for answers, (w, e) in itertools.product(ANSWERS, chosen)]
    baseline = pd.Series({f"{w}|{IN_MODEL}": no_search(
        values_for(w, e, grid, part.objective), grid, priors[w]) for w, e in chosen})
    tasks = [(job, seed, tuple(args.searchers)) for job in jobs for seed in job.seeds]
    print(f"{len(chosen)} workers x {len(ANSWERS)} answer models x {args.runs} runs, "
          f"searchers {', '.join(args.searchers)}, up to {max(args.budgets)} handovers; "
          f"{len(tasks)} jobs on {args.jobs} processes", flush=True)
    started, rows = time.perf_counter(), []
    with multiprocessing.get_context("fork").Pool(args.jobs) as pool:
        for done, found in enumerate(pool.imap_unordered(one_seed, tasks), start=1):
            rows += found
            if done % max(1, len(tasks) // 20) == 0 or done == len(tasks):
                print(f"  {done}/{len(tasks)} jobs, {time.perf_counter() - started:.0f} s",
                      flush=True)
    runs = pd.DataFrame(rows)
    each = runs.drop_duplicates(["searcher", "answers", "worker", "seed"]).groupby("searcher")
    seconds, fits = each["seconds"].mean(), each[["fits", "failed_fits"]].sum()
    summary = measured_summary(runs, baseline, args.seed)
    columns = ["answers", "budget", "searcher", "n_workers", "n_runs", "p_regret_0", "ci_low",
               "ci_high", "mean_regret", "regret_ci_low", "regret_ci_high", "gain",
               "gain_ci_low", "gain_ci_high", "harm", "harm_ci_low", "harm_ci_high"]
    pd.set_option("display.width", 200)
    print("\nPer searcher (P(optimum), mean true regret, gain over no search, harm; 95 % "
          "intervals over workers):")
    print(summary[columns].round(3).to_string(index=False))
    for other in args.searchers[1:]:
        print(f"\n{other} − {args.searchers[0]}, paired by worker and seed (95 % bootstrap "
              "over workers; regret < 0: BoTorch better):")
        print(paired(runs, args.searchers[0], other, args.seed).round(3).to_string(index=False))
    print("\nMean seconds a run (up to the largest budget): "
          + ", ".join(f"{k} {v:.1f}" for k, v in seconds.items()))
    for name, (made, failed) in fits.iterrows():
        if made:
            print(f"{name}: {failed} of {made} kernel fits failed ({failed / made:.0%}; "
                  "those kept BoTorch's default kernel at its priors' modes)")
    print(f"Wall time {time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
