"""How far can the fine warm start trust its interpolation? Today's solve (10 iterations from the
coarse lattice) beside the checked fine warm start (``SolverSettings(warm_start="fine")``:
today's solves at the nodes of a lattice every ``fine_spacing``, interpolated and scored; the
locations whose cell fails the check of ``FineLattice.unsure`` solved as today): the share of
locations re-solved, the share scoring identically, how the others differ, and the time.

Usage: python experiments/tools/warm_start_agreement.py [--locations 20000] [--seed 0]
       [--spacings 0.006,0.009] [--checks 0,0.1,0.2,0.5,10] [--reference 60]

Random points of the paper's 3 mm paper-code grid, default worker and task, one process. Per
spacing and check (``fine_check_deg``; at 0 only cells whose eight corners all score as the
location are trusted, at 10 nearly every cell with one corner that does): the share re-solved,
the share whose flags and, where feasible, paper score, REBA and RULA all equal today's (as a
landscape stores them), and those that equal a converged solve's (``--reference`` iterations
from the coarse lattice; today's own agreement with it is printed first); then where the two
differ — flags, the paper score's and REBA's change where both are feasible, the mean height of
the differing points, the share at the paper score's minimum — and the time per location against
today's with the lattice's nodes already solved (random points share few nodes, so on a whole
grid the nodes cost more than here: ``experiments/bench_sweep.py --compare`` times the two
sweeps end to end). A figure, not a test.
"""

from __future__ import annotations

import argparse
import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import time  # noqa: E402
from dataclasses import replace  # noqa: E402

import numpy as np  # noqa: E402

from ergohandover.landscape.grid import Grid, parse_boundary  # noqa: E402
from ergohandover.twin.evaluate import Evaluator, evaluate_batch, posture_solver  # noqa: E402
from ergohandover.twin.warm_start import FineLattice  # noqa: E402

COLUMNS = ("flags", "paper_postural", "reba", "rula")


def numbers(text: str, kind=float) -> list:
    return [kind(v) for v in text.split(",")]


def same(found: dict, other: dict) -> np.ndarray:
    """(N,) bool: identical as a landscape stores them — the flags, and where feasible the
    scores (an infeasible location's scores are not kept)."""
    flags = np.asarray(found["flags"])
    equal = flags == np.asarray(other["flags"])
    for column in COLUMNS[1:]:
        equal &= (flags != 0) | (np.asarray(found[column]) == np.asarray(other[column]))
    return equal


def differences(found: dict, today: dict, points: np.ndarray) -> str:
    """Where ``found`` differs from ``today``: one line of shares [%] and heights [m]."""
    flags = np.asarray(found["flags"]) != np.asarray(today["flags"])
    both = (np.asarray(found["flags"]) == 0) & (np.asarray(today["flags"]) == 0)
    paper = np.abs(np.asarray(found["paper_postural"], float)
                   - np.asarray(today["paper_postural"], float))[both]
    reba = np.asarray(found["reba"])[both] != np.asarray(today["reba"])[both]
    moved = ~same(found, today)
    low = min(np.asarray(today["paper_postural"])[both].min(),
              np.asarray(found["paper_postural"])[both].min())
    at_min = [100 * np.mean(np.asarray(r["paper_postural"])[np.asarray(r["flags"]) == 0] == low)
              for r in (today, found)]
    return (f"flags differ {100 * flags.mean():.2f}%; both feasible: paper score moves by 1 at "
            f"{100 * np.mean(paper == 1):.2f}%, by 2 or more at {100 * np.mean(paper >= 2):.2f}%,"
            f" REBA differs at {100 * reba.mean():.2f}%; differing points' mean height "
            f"{f'{points[moved, 1].mean():.2f} m' if moved.any() else '-'} (all "
            f"{points[:, 1].mean():.2f} m); paper score "
            f"{low:.0f} at {at_min[0]:.2f}% of feasible points today, {at_min[1]:.2f}% here")


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--locations", type=int, default=20000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--spacings", type=numbers, default=[0.006, 0.009])
    parser.add_argument("--checks", type=numbers, default=[0.0, 0.1, 0.2, 0.5, 10.0])
    parser.add_argument("--reference", type=int, default=60)
    args = parser.parse_args()
    evaluator = Evaluator()
    boundary = parse_boundary("paper-code", evaluator.body, evaluator.task)
    grid = Grid(boundary, 0.003)
    rng = np.random.default_rng(args.seed)
    points = grid.coordinates(np.sort(rng.choice(grid.size, args.locations, replace=False)))
    posture_solver(evaluator, points)  # lattice nodes and kernel, outside the timing
    start = time.perf_counter()
    today = evaluate_batch(evaluator, points)
    today_s = time.perf_counter() - start
    print(f"{args.locations:,} points of the 3 mm paper-code grid (seed {args.seed}); today's "
          f"solve {1e6 * today_s / len(points):.0f} us/location")
    reference = replace(evaluator, settings=replace(evaluator.settings,
                                                    iterations=args.reference))
    converged = evaluate_batch(reference, points)
    print(f"today's solve scores as a {args.reference}-iteration one at "
          f"{100 * same(today, converged).mean():.2f}% of them")
    unsure = FineLattice.unsure.__func__
    redone = []

    def counted(cls, *arguments):  # the share each call re-solves, for the report
        found = unsure(cls, *arguments)
        redone.append(found)
        return found

    FineLattice.unsure = classmethod(counted)
    for h in args.spacings:
        for check in args.checks:
            fine = replace(evaluator, settings=replace(
                evaluator.settings, warm_start="fine", fine_spacing=h, fine_check_deg=check))
            evaluate_batch(fine, points)  # the nodes, solved outside the timing
            redone.clear()
            start = time.perf_counter()
            found = evaluate_batch(fine, points)
            took = time.perf_counter() - start
            share = 100 * np.concatenate(redone).mean()
            agree = [100 * same(found, other).mean() for other in (today, converged)]
            print(f"spacing {h:.3f} m, check {check:g} deg: re-solved {share:.2f}%, as today's "
                  f"{agree[0]:.2f}%, as {args.reference} iterations {agree[1]:.2f}%, time "
                  f"{took / today_s:.2f} of today's (nodes solved)\n  "
                  + differences(found, today, points))


if __name__ == "__main__":
    main()
