"""Benchmark: score 1 M random postures with REBA + RULA + the paper's score; print postures/s.

Usage: python experiments/bench_scoring.py [--postures N] [--repeats K] [--seed S]

Postures are drawn once (validation is not timed); each repeat scores all of them with
:func:`ergohandover.ergonomics.score_postures` in one process, on one core. The best and
median repeat are printed. A figure, not a test: the machine may be shared and noisy.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import numpy as np

from ergohandover.ergonomics import Posture, score_postures

TARGET_PER_S = 2_000_000


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--postures", type=int, default=1_000_000, help="postures per repeat")
    parser.add_argument("--repeats", type=int, default=5, help="timed repeats")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random postures")
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


if __name__ == "__main__":
    main()
