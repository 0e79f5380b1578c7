"""Benchmark: score 1 M random postures with REBA + RULA + the paper's score; print postures/s.
Then the same under posture-measurement error: 250 postures x 4,000 measured copies each (1 M
measured postures, as the robustness part scores a location) through the Monte Carlo, whose
rate is printed as a ratio to plain scoring measured in the same run. Last, OWAS, the static
back load and the revised NIOSH lifting equation on the same postures, each as a ratio to REBA
alone in the same run.

Usage: python experiments/bench_scoring.py [--postures N] [--repeats K] [--seed S]
                                           [--locations L] [--draws D]

Postures are drawn once (validation is not timed); each repeat scores all of them with
:func:`ergohandover.ergonomics.score_postures` in one process, on one core. The Monte Carlo
(:func:`ergohandover.robustness.posture_error.monte_carlo`) adds drawing the errors, clipping
the measured angles and the summaries (mean, quantiles, item flips);
:func:`~ergohandover.robustness.posture_error.expected_scores` is the robust search's ranking
(common errors, one score). The best and median repeat are printed. A figure, not a test: the
machine may be shared and noisy.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import numpy as np

from ergohandover.ergonomics import Posture, ScoringSettings, score_postures
from ergohandover.ergonomics.reba import reba
from ergohandover.robustness.posture_error import ErrorModel, expected_scores, monte_carlo
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.workload import Levers, LiftTask, back_load, lift_at, owas

TARGET_PER_S = 2_000_000


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--postures", type=int, default=1_000_000, help="postures per repeat")
    parser.add_argument("--repeats", type=int, default=5, help="timed repeats")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random postures")
    parser.add_argument("--locations", type=int, default=250,
                        help="postures measured with error (default: 250)")
    parser.add_argument("--draws", type=int, default=4000,
                        help="measured copies of each (default: 4000, the study's)")
    args = parser.parse_args()

    posture = Posture.random(args.postures, np.random.default_rng(args.seed))
    score_postures(posture.take(np.arange(1000)))  # warm-up
    times = []
    for _ in range(args.repeats):
        start = time.perf_counter()
        scores = score_postures(posture)
        times.append(time.perf_counter() - start)
    best, median = min(times), statistics.median(times)
    print(f"machine: {platform.processor() or platform.machine()}, numpy {np.__version__}")
    print(f"scored {args.postures:,} postures x {args.repeats} repeats "
          f"({len(scores)} score columns: REBA + RULA + paper_postural)")
    print(f"best:   {args.postures / best:,.0f} postures/s ({best * 1e3:.0f} ms)")
    print(f"median: {args.postures / median:,.0f} postures/s ({median * 1e3:.0f} ms)")
    verdict = "meets" if args.postures / median >= TARGET_PER_S else "MISSES"
    print(f"target: {TARGET_PER_S:,} postures/s -> median {verdict} it")

    # Under posture error: each location's measured copies, scored and summarised.
    located = posture.take(np.arange(args.locations))
    model, measured = ErrorModel(5.0), args.locations * args.draws
    runs = {"monte_carlo (3 scores, flips, quantiles)": lambda rng: monte_carlo(
                located, model, args.draws, rng),
            "expected_scores (common errors, 1 score)": lambda rng: expected_scores(
                located, model, args.draws, int(rng.integers(2**31)))}
    print(f"\nunder 5 deg of posture error: {args.locations} postures x {args.draws:,} draws "
          f"= {measured:,} measured postures per repeat")
    for name, run in runs.items():
        rng = np.random.default_rng(args.seed)
        times = []
        for _ in range(args.repeats):
            start = time.perf_counter()
            run(rng)
            times.append(time.perf_counter() - start)
        rate = measured / statistics.median(times)
        print(f"{name}: median {rate:,.0f} measured postures/s, "
              f"{rate / (args.postures / median):.2f} x plain scoring")
    workload(posture, args)


def median_rate(run, n: int, repeats: int) -> float:
    """Items a second of the median of ``repeats`` timed calls of ``run``."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return n / statistics.median(times)


def workload(posture: Posture, args: argparse.Namespace) -> None:
    """OWAS, the static back load and the lifting equation on the same postures, each as a
    ratio to REBA alone timed in the same run."""
    settings, levers = ScoringSettings(), Levers.of(BodySpec())
    rng = np.random.default_rng(args.seed)
    locations = np.column_stack([rng.uniform(-0.3, 0.3, posture.n),
                                 rng.uniform(0.5, 1.6, posture.n),
                                 rng.uniform(0.2, 0.7, posture.n)])
    reba_rate = median_rate(lambda: reba(posture, settings), posture.n, args.repeats)
    print(f"\nworkload beside REBA alone ({reba_rate:,.0f} postures/s), "
          f"{posture.n:,} postures, median of {args.repeats}:")
    for name, run in (("OWAS", lambda: owas(posture)),
                      ("static back load", lambda: back_load(posture, levers)),
                      ("lifting equation", lambda: lift_at(locations, posture["load_kg"],
                                                           posture["coupling"], LiftTask()))):
        rate = median_rate(run, posture.n, args.repeats)
        print(f"{name}: {rate:,.0f} postures/s, {rate / reba_rate:.2f} x REBA")


if __name__ == "__main__":
    main()
