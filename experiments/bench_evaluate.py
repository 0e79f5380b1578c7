"""Benchmark: the full pipeline (solve + angles + every score) over random box locations.

Usage: python experiments/bench_evaluate.py [--locations N] [--workers W] [--seed S]
       [--pybullet-locations M] [--boundary body|paper-code]

Locations are drawn uniformly in the default worker's boundary. Printed, from one run:

- setup: numba compile (or load from its on-disk cache) and the warm-start lattice nodes the
  locations need, once per process tree, before any worker forks;
- the single-process rate of the whole pipeline (``evaluate(..., workers=1)``);
- the rate over ``--workers`` processes (``evaluate(..., workers=W)``);
- PyBullet's own IK (``PyBulletSolver.solve``: calculateInverseKinematics2 on both hands,
  from rest) on the first ``--pybullet-locations`` of the same locations, and the ratio.

Worker processes use one BLAS thread each; run with ``OMP_NUM_THREADS=1`` (set here when
unset) so that the single-process figure is per core too. A figure, not a test.
"""

from __future__ import annotations

import argparse
import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import platform  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from ergohandover.twin.anthropometry import BodySpec  # noqa: E402
from ergohandover.twin.evaluate import Evaluator, evaluate, posture_solver  # noqa: E402
from ergohandover.twin.pybullet_ik import PyBulletSolver  # noqa: E402
from ergohandover.twin.task import Boundary, TaskSpec  # noqa: E402

TARGET_PER_S = 27_000  # the 3 mm paper-code grid (3.26 M locations) in 2 minutes


def _rate(n: int, seconds: float) -> str:
    return f"{n:,} locations in {seconds:.2f} s: {n / seconds:,.0f} locations/s"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--locations", type=int, default=200_000)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--pybullet-locations", type=int, default=300,
                        help="locations for PyBullet's IK, a prefix of the same locations")
    parser.add_argument("--boundary", choices=("body", "paper-code"), default="paper-code")
    args = parser.parse_args()

    body, task = BodySpec(), TaskSpec()
    boundary = (Boundary.paper_code() if args.boundary == "paper-code"
                else Boundary.from_body(body, task))
    locations = boundary.sample(args.locations, np.random.default_rng(args.seed))
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores; boundary {args.boundary}; "
          f"{args.workers} worker process(es)")

    start = time.perf_counter()
    posture_solver(Evaluator(body, task), locations)
    print(f"setup (numba compile or cache load + warm-start lattice nodes): "
          f"{time.perf_counter() - start:.2f} s, once per process tree")

    start = time.perf_counter()
    table = evaluate(locations, Evaluator(body, task), workers=1)
    elapsed = time.perf_counter() - start
    single = len(locations) / elapsed
    print(f"1 process:  {_rate(len(locations), elapsed)} "
          "(solve + angles + REBA/RULA/paper scores)")
    start = time.perf_counter()
    evaluate(locations, Evaluator(body, task), workers=args.workers)
    elapsed = time.perf_counter() - start
    rate = len(locations) / elapsed
    print(f"{args.workers} processes: {_rate(len(locations), elapsed)}")
    print(f"feasible: {table['feasible'].mean():.1%}; reasons: "
          f"{table['reason'][table['reason'] != ''].value_counts().to_dict()}")

    subset = locations[:args.pybullet_locations]
    ik = PyBulletSolver(body, task)
    ik.solve(subset[:1])  # connect and load the URDF outside the timing
    start = time.perf_counter()
    solution = ik.solve(subset)
    elapsed = time.perf_counter() - start
    pybullet = len(subset) / elapsed
    print(f"PyBullet IK (calculateInverseKinematics2, both hands, from rest): "
          f"{_rate(len(subset), elapsed)}; "
          f"{(solution.hand_error < 0.01).mean():.0%} within 1 cm")
    print(f"whole-body solver + scoring vs PyBullet IK alone: {single / pybullet:,.0f}x per "
          f"process, {rate / pybullet:,.0f}x on {args.workers} processes")
    print(f"target: {TARGET_PER_S:,} locations/s ({3_261_694:,} paper-code 3 mm points in "
          f"2 min) -> {'meets' if rate >= TARGET_PER_S else 'MISSES'} it at {rate:,.0f}/s; "
          f"3 mm grid would take {3_261_694 / rate / 60:.1f} min")


if __name__ == "__main__":
    main()
