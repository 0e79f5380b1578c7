"""Benchmark of the carry planner: the paper's five starts to the default optimum.

Usage: python experiments/bench_planning.py [--workers N] [--seed S]

Prints, per start, the planning time, the robot poses checked and the waypoints; then the
median planning time and plans per second over the five, on one process and on ``--workers``.
Reference measured in the same run: the time of one robot pose check (PyBullet's IK for both
arms, seeded by a pose 2 cm away, and the collision tests), so that the planning time also
reads as "poses' worth" and the share of it spent in the checks, figures that mean something
on a shared machine where absolute times do not.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from ergohandover.scene.carries import CarryJob, plan_carries
from ergohandover.scene.robot import GRASPS
from ergohandover.scene.world import WorkerPosture, World
from ergohandover.study.baselines.comparison import PAPER_STARTS
from ergohandover.study.landscape.recorded import recorded_optimum
from ergohandover.twin.evaluate import Evaluator, evaluate, joint_angles, posture_solver

OPTIMUM = recorded_optimum(Path(__file__).resolve().parents[1] / "results")
"""The study's paper-score optimum, as results/landscape/stats.csv records it."""


def pose_check_s(repeats: int = 200) -> float:
    """Seconds per seeded robot pose check along a short line from start 1 toward the worker."""
    with World() as world:
        start = PAPER_STARTS[0]
        reach = world.reach(start, grasps=[GRASPS[0]], lift=0.3)
        q, began = reach.q, time.perf_counter()
        for f in np.linspace(0.0, 0.4, repeats):
            point = start + np.array([0.0, 0.0, -f])
            step = world.reach(point, grasps=[GRASPS[0]], seed=q, lift=0.3)
            q = step.q if step.reachable else q
        return (time.perf_counter() - began) / repeats


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    parser.add_argument("--seed", type=int, default=0, help="planner seed (default 0)")
    args = parser.parse_args()
    names = posture_solver(Evaluator()).model.joint_names
    posture = WorkerPosture(names, joint_angles(evaluate(OPTIMUM[None], joints=True))[0])
    jobs = [CarryJob(start, OPTIMUM, posture) for start in PAPER_STARTS]
    check = pose_check_s()
    print(f"reference: one robot pose check {1000 * check:.1f} ms")
    for workers in sorted({1, args.workers}):
        began = time.perf_counter()
        plans = list(plan_carries(jobs, seed=args.seed, workers=workers))
        wall = time.perf_counter() - began
        if workers == 1:
            for number, plan in enumerate(plans, 1):
                print(f"start {number}: {plan.reason or 'planned'}, {plan.planning_s:.1f} s, "
                      f"{plan.checks} poses checked ({plan.checks * check:.1f} s of checks), "
                      f"{len(plan.waypoints)} waypoints, {plan.length_m:.2f} m")
        times = [plan.planning_s for plan in plans]
        share = sum(p.checks for p in plans) * check / sum(times)
        print(f"{workers} process(es): {sum(p.ok for p in plans)}/5 planned, median planning "
              f"{statistics.median(times):.1f} s ({statistics.median(times) / check:.0f} pose "
              f"checks' worth; {share:.0%} of the time in the checks), "
              f"{len(plans) / wall:.3f} plans/s ({wall:.1f} s wall)")


if __name__ == "__main__":
    main()
