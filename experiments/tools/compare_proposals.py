"""The fitted twin's two proposals side by side: the most telling handover (the default) and
the most probable optimum untried (greedy).

Usage: python experiments/tools/compare_proposals.py [--workers 31-60] [--runs 3]
       [--budget 10] [--answers posture:5|imu:1]

Runs the fitted twin as the personalisation study runs it (near_ties.py: the study's seeds,
candidates and answers; the landscapes from the cache) once with each proposal, on the same
runs (the same seeds, so the same measurement errors at any cell both ask), and prints the
share of runs recommending the worker's true optimum under each, the paired difference with a
bootstrap interval over workers, and the runs only one of them got right. The default workers
are the population's 31-60: not the study's 30, so that choosing the proposal here does not
tune it to the runs the study reports.
"""

from __future__ import annotations

import argparse

import numpy as np
import pandas as pd
from near_ties import fitted_twin_runs

from ergohandover.study.personalise import measured_answers as measured

BOOTSTRAP = 2000


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", default="31-60", help="the population's sampled workers, "
                        "first-last (default 31-60: outside the study's)")
    parser.add_argument("--runs", type=int, default=3, help="runs per worker (default 3)")
    parser.add_argument("--budget", type=int, default=10, help="handovers (default 10)")
    parser.add_argument("--answers", default="posture:5",
                        help="KIND:LEVEL as the study's answer models (default posture:5)")
    args = parser.parse_args()
    kind, level = args.answers.split(":")
    answers = measured.Answers(kind, float(level))
    rows = []
    for lookahead in (True, False):
        for i, (worker, values, searcher) in enumerate(fitted_twin_runs(
                args.workers, args.runs, args.budget, answers, lookahead=lookahead)):
            chosen = searcher.recommend()
            rows.append({"lookahead": lookahead, "worker": worker, "run": i,
                         "found": bool(values[chosen.cell] == values.min()),
                         "regret": float(values[chosen.cell] - values.min()),
                         "stated": chosen.p_optimal})
        print(f"{'most telling' if lookahead else 'greedy'}: done", flush=True)
    runs = pd.DataFrame(rows)
    paired = runs.pivot(index=["worker", "run"], columns="lookahead", values="found")
    per_worker = (paired[True].astype(float) - paired[False].astype(float)).groupby(
        level="worker").mean().to_numpy()
    rng = np.random.default_rng(0)
    draws = rng.choice(per_worker, (BOOTSTRAP, len(per_worker))).mean(axis=1)
    low, high = np.percentile(draws, [2.5, 97.5])
    for lookahead, name in ((True, "most telling"), (False, "greedy")):
        mine = runs[runs["lookahead"] == lookahead]
        print(f"{name}: P(true optimum) {mine['found'].mean():.0%}, mean true regret "
              f"{mine['regret'].mean():.2f}, stated {mine['stated'].mean():.0%} "
              f"({len(mine)} runs)")
    print(f"most telling - greedy: {per_worker.mean():+.1%} ({low:+.1%} to {high:+.1%}, "
          f"{len(per_worker)} workers); only the most telling found it in "
          f"{int((paired[True] & ~paired[False]).sum())} runs, only greedy in "
          f"{int((~paired[True] & paired[False]).sum())} ({args.answers}, {args.budget} "
          "handovers)")


if __name__ == "__main__":
    main()
