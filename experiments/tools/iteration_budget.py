"""How many solver iterations are enough? Scores and feasibility at several budgets against a
long solve from the same warm start, with the time each budget takes.

Usage: python experiments/tools/iteration_budget.py [--locations 20000] [--seed 1]
       [--budgets 8,9,10,11,12] [--reference 60]

Random locations in the paper-code boundary, default worker and task, one process. For each
budget it prints the share of locations whose flags, paper score, REBA and RULA all equal the
reference's (a ``--reference``-iteration solve) and those of a 12-iteration solve, and the time
per location. A figure for choosing ``SolverSettings.iterations``, not a test.
"""

from __future__ import annotations

import argparse
import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import time  # noqa: E402

import numpy as np  # noqa: E402

from ergohandover.twin.evaluate import Evaluator, evaluate_batch, posture_solver  # noqa: E402
from ergohandover.twin.solver import SolverSettings  # noqa: E402
from ergohandover.twin.task import Boundary  # noqa: E402

COLUMNS = ("flags", "paper_postural", "reba", "rula")


def scores(locations: np.ndarray, iterations: int) -> tuple[dict, float]:
    """The COLUMNS at ``iterations`` and the seconds per location."""
    evaluator = Evaluator(settings=SolverSettings(iterations=iterations))
    posture_solver(evaluator, locations)  # lattice nodes outside the timing
    start = time.perf_counter()
    out = evaluate_batch(evaluator, locations, COLUMNS)
    return out, (time.perf_counter() - start) / len(locations)


def same(a: dict, b: dict) -> float:
    """Share of locations where every column agrees."""
    return float(np.all([a[c] == b[c] for c in COLUMNS], axis=0).mean())


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--locations", type=int, default=20_000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--budgets", default="8,9,10,11,12")
    parser.add_argument("--reference", type=int, default=60)
    args = parser.parse_args()
    locations = Boundary.paper_code().sample(args.locations, np.random.default_rng(args.seed))
    reference, _ = scores(locations, args.reference)
    twelve, _ = scores(locations, 12)
    print(f"{args.locations:,} paper-code locations (seed {args.seed}); agreement of flags, "
          f"paper score, REBA and RULA")
    print(f"{'iterations':>10} {'us/location':>12} {f'vs {args.reference}':>8} {'vs 12':>8}")
    for budget in (int(b) for b in args.budgets.split(",")):
        out, seconds = scores(locations, budget)
        print(f"{budget:>10} {seconds * 1e6:>12.0f} {same(out, reference):>8.2%} "
              f"{same(out, twelve):>8.2%}")


if __name__ == "__main__":
    main()
