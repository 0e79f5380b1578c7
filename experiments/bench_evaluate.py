"""Benchmark: the full pipeline (solve + angles + every score) over random box locations.

Usage: python experiments/bench_evaluate.py [--locations N] [--workers W] [--seed S]
       [--solver numpy|pybullet]

Locations are drawn uniformly in the default worker's ``body`` boundary. The warm-start
lattice is solved first (once per worker and task, reported separately); the timed run is one
``evaluate()`` call over all locations using ``--workers`` processes. A figure, not a test.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np

from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator, evaluate, posture_solver
from ergohandover.twin.task import Boundary, TaskSpec

TARGET_PER_S = 10_000


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--locations", type=int, default=20_000)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--solver", choices=("numpy", "pybullet"), default="numpy")
    args = parser.parse_args()

    body, task = BodySpec(), TaskSpec()
    boundary = Boundary.from_body(body, task)
    locations = boundary.sample(args.locations, np.random.default_rng(args.seed))
    start = time.perf_counter()
    posture_solver(Evaluator(body, task, args.solver))
    setup = time.perf_counter() - start
    start = time.perf_counter()
    table = evaluate(locations, body, task, solver=args.solver, workers=args.workers)
    elapsed = time.perf_counter() - start
    rate = len(locations) / elapsed
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores; solver {args.solver}, "
          f"{args.workers} worker process(es)")
    (x0, x1), (y0, y1), (z0, z1) = boundary.x, boundary.y, boundary.z
    print(f"boundary 'body': x {x0:+.3f}..{x1:+.3f}, y {y0:.3f}..{y1:.3f}, "
          f"z {z0:.3f}..{z1:.3f} m")
    print(f"setup (warm-start lattice): {setup:.2f} s, once per worker and task")
    print(f"evaluated {len(locations):,} locations in {elapsed:.2f} s: {rate:,.0f} locations/s "
          f"(solve + angles + REBA/RULA/paper scores)")
    print(f"feasible: {table['feasible'].mean():.1%}; reasons: "
          f"{table['reason'][table['reason'] != ''].value_counts().to_dict()}")
    print(f"target: {TARGET_PER_S:,} locations/s -> {'meets' if rate >= TARGET_PER_S else 'MISSES'}"
          f" it (the paper: ~315/s in Unity)")


if __name__ == "__main__":
    main()
