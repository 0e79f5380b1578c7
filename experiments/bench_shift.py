"""Benchmark: a shift's columns (each joint's load share, a shift of handovers, LiFFT's dose)
against the posture solve they read, per location, on the default worker's 1 cm grid; printed
as a ratio measured in the same run, at each rate.

Usage: python experiments/bench_shift.py [--cells N] [--seed S] [--rates R ...] [--hold S]

``--cells`` locations are drawn (seeded) from the population grid of the 50th-percentile man;
their postures are solved in this process, on one core (the solver's warm-start lattice first,
untimed), then their shift columns are computed from those postures for an 8-hour shift at each
rate. The target: the shift costs no more than the posture solve (a ratio of at most 1). A
figure, not a test: the machine may be shared and noisy; the ratio is what means something.
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

from ergohandover.ergonomics import Posture
from ergohandover.ergonomics.posture import REQUIRED_COLUMNS
from ergohandover.study.config import StudyConfig
from ergohandover.study.shared import grid_of
from ergohandover.twin.evaluate import evaluate_arrays
from ergohandover.workload.fatigue import Shift
from ergohandover.workload.strength import shift_columns


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--cells", type=int, default=4000, help="locations (default: 4000)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the locations")
    parser.add_argument("--rates", type=float, nargs="+", default=[1.0, 6.0],
                        help="handovers a minute (default: 1 6)")
    parser.add_argument("--hold", type=float, default=3.0, help="hold [s] (default: 3)")
    args = parser.parse_args()

    config = StudyConfig()
    evaluator = config.evaluator(config.population.reference)
    grid = grid_of(evaluator, config.population.boundary, config.population.step)
    rng = np.random.default_rng(args.seed)
    cells = np.sort(rng.choice(grid.size, min(args.cells, grid.size), replace=False))
    locations = grid.coordinates(cells)
    evaluate_arrays(locations[:8], evaluator)  # the warm-start lattice and imports, untimed
    start = time.perf_counter()
    rows = evaluate_arrays(locations, evaluator)
    solve = time.perf_counter() - start
    feasible = rows["flags"] == 0
    columns = {name: np.asarray(rows[name], float)[feasible] for name in REQUIRED_COLUMNS}
    posture = Posture(columns)
    print(f"machine: {platform.processor() or platform.machine()}, numpy {np.__version__}")
    print(f"posture solve: {len(cells):,} locations in {solve:.2f} s "
          f"({1e3 * solve / len(cells):.3f} ms each); {int(feasible.sum()):,} feasible")
    for rate in args.rates:
        plan = Shift(rate, args.hold, 8.0)
        start = time.perf_counter()
        shift_columns(posture, evaluator.body, plan)
        took = time.perf_counter() - start
        print(f"shift at {rate:g} a minute, {args.hold:g} s holds ({plan.handovers:,} handovers): "
              f"{1e3 * took:.1f} ms, {took / solve:.3f} x the posture solve (target: at most 1)")


if __name__ == "__main__":
    main()
