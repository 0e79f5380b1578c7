"""Benchmark: the viewer's box move, from the new location to the updated scene.

Usage: python experiments/bench_viewer.py [--moves N] [--seed S] [--no-robot]

A viewer is started on a free local port (no browser attached: what is timed is the server's
side of a move) with a 4 cm landscape of the default worker. Each move is
``HandoverViewer.move_to``, the function a gizmo drag or a typed field calls: the twin
re-solved at the location (the whole-body solver and every score), the robot holding the box
there (its IK), the panel's text, and every link's pose sent to the scene. The reference,
measured in the same run on the same locations: PyBullet's own IK of the twin's two hands
(``PyBulletSolver.solve``, calculateInverseKinematics2 from standing), which finds a posture and
nothing else. Locations are drawn uniformly in the paper's boundary. A figure, not a test.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import numpy as np

from ergohandover.landscape.grid import Grid, parse_boundary
from ergohandover.landscape.store import landscape_of
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.pybullet_ik import PyBulletSolver
from ergohandover.viewer.app import HandoverViewer, free_port, start_server

TARGET_MS = 50.0


def timed(function, locations) -> list[float]:
    """Milliseconds of ``function(location)`` for each location."""
    times = []
    for location in locations:
        start = time.perf_counter()
        function(location)
        times.append(1000 * (time.perf_counter() - start))
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--moves", type=int, default=200, help="box moves timed")
    parser.add_argument("--seed", type=int, default=0, help="seed of the locations")
    parser.add_argument("--no-robot", action="store_true",
                        help="moves without the robot's IK (the twin and the scene only)")
    args = parser.parse_args()

    evaluator = Evaluator()
    boundary = parse_boundary("paper-code", evaluator.body, evaluator.task)
    landscape = landscape_of(evaluator, Grid(boundary, 0.04))
    rng = np.random.default_rng(args.seed)
    locations = rng.uniform(boundary.lower, boundary.upper, size=(args.moves, 3))
    viewer = HandoverViewer(evaluator, landscape, {"start": locations[0]}, [],
                            start_server("127.0.0.1", free_port()))
    viewer.scene.with_robot = not args.no_robot
    try:
        timed(viewer.move_to, locations[:5])  # warm-up
        moves = timed(viewer.move_to, locations)
        feasible = sum(viewer.scene.solve(loc).feasible for loc in locations[:50])
    finally:
        viewer.close()
    ik = PyBulletSolver(evaluator.body, evaluator.task)
    ik.solve(locations[:2])  # warm-up (its client, its model)
    reference = timed(lambda loc: ik.solve(loc[None]), locations)
    move_ms, ik_ms = statistics.median(moves), statistics.median(reference)
    print(f"machine: {platform.processor() or platform.machine()}, "
          f"{'without' if args.no_robot else 'with'} the robot's IK, "
          f"{args.moves} moves ({feasible} of the first 50 feasible)")
    print(f"viewer move (re-solve + scores + robot + scene): median {move_ms:.1f} ms, "
          f"90th percentile {np.percentile(moves, 90):.1f} ms")
    print(f"PyBullet IK of the same moves (posture only):     median {ik_ms:.1f} ms, "
          f"90th percentile {np.percentile(reference, 90):.1f} ms")
    print(f"ratio: a viewer move takes {move_ms / ik_ms:.2f} x PyBullet's IK")
    verdict = "meets" if move_ms <= TARGET_MS else "MISSES"
    print(f"target: median <= {TARGET_MS:g} ms -> {verdict} it")


if __name__ == "__main__":
    main()
