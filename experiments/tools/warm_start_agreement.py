"""Could a better warm start make the sweep faster without changing its scores? Today's solve
(10 iterations from the coarse lattice) beside solves of a few iterations from a fine lattice of
today's own results, interpolated: the share of locations scoring identically and the time.

Usage: python experiments/tools/warm_start_agreement.py [--locations 20000] [--seed 0]
       [--spacings 0.01,0.015,0.02] [--iterations 1,2,3,4]

Random points of the paper's 3 mm paper-code grid, default worker and task, one process. The
fine lattice covers the boundary with a node beyond each face, each node solved as today's
sweep solves it; a location starts from the trilinear interpolation of its cell (a function of
the location alone, as the issue requires). A row per spacing and iteration count: the share
whose flags, paper score, REBA and RULA all equal today's, and those that equal a converged
solve's (``--reference`` iterations from the coarse lattice; today's own agreement with it is
printed first), the time per location against today's, and the lattice's own cost in
locations of today's solve. A figure, not a test.
"""

from __future__ import annotations

import argparse
import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import time  # noqa: E402

import numpy as np  # noqa: E402

from ergohandover.landscape.grid import Grid, parse_boundary  # noqa: E402
from ergohandover.twin.evaluate import Evaluator, evaluate_batch, posture_solver  # noqa: E402
from ergohandover.twin.warm_start import StartLattice  # noqa: E402

COLUMNS = ("flags", "paper_postural", "reba", "rula")


def numbers(text: str, kind=float) -> list:
    return [kind(v) for v in text.split(",")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--locations", type=int, default=20000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--spacings", type=numbers, default=[0.01, 0.015, 0.02])
    parser.add_argument("--iterations", type=lambda t: numbers(t, int), default=[1, 2, 3, 4])
    parser.add_argument("--reference", type=int, default=60)
    args = parser.parse_args()
    evaluator = Evaluator()
    boundary = parse_boundary("paper-code", evaluator.body, evaluator.task)
    grid = Grid(boundary, 0.003)
    rng = np.random.default_rng(args.seed)
    points = grid.coordinates(np.sort(rng.choice(grid.size, args.locations, replace=False)))
    solver = posture_solver(evaluator)
    start = time.perf_counter()
    today = evaluate_batch(evaluator, points)
    today_s = time.perf_counter() - start
    print(f"{args.locations:,} points of the 3 mm paper-code grid (seed {args.seed}); today's "
          f"solve {1e6 * today_s / len(points):.0f} us/location")
    solve = solver.solve

    def agree(found: dict, other: dict) -> float:
        same = np.ones(len(points), dtype=bool)
        for column in COLUMNS:
            same &= found[column] == other[column]
        return 100 * same.mean()

    solver.solve = lambda where: solver.iterate(where, solver.lattice.start(where), args.reference)
    converged = evaluate_batch(evaluator, points)
    solver.solve = solve
    print(f"today's solve scores as a {args.reference}-iteration one at "
          f"{agree(today, converged):.2f}% of them")
    print(f"spacing  iterations  as today's  as {args.reference} iterations  time vs today  "
          "lattice nodes")
    try:
        for h in args.spacings:
            axes = tuple(np.arange(lo - h, hi + 2 * h, h)
                         for lo, hi in zip(boundary.lower, boundary.upper, strict=True))
            nodes = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
            q = solve(nodes).q.reshape(*(len(a) for a in axes), -1)
            fine = StartLattice(axes, q, None)
            for k in args.iterations:
                solver.solve = lambda where, k=k, fine=fine: solver.iterate(
                    where, fine.start(where), k)
                start = time.perf_counter()
                found = evaluate_batch(evaluator, points)
                took = time.perf_counter() - start
                solver.solve = solve
                print(f"{h:7.3f}  {k:10d}  {agree(found, today):9.2f}%  "
                      f"{agree(found, converged):16.2f}%  {took / today_s:13.2f}  "
                      f"{len(nodes):,} ({len(nodes) / grid.size:.3f} of the grid)")
    finally:
        solver.solve = solve


if __name__ == "__main__":
    main()
