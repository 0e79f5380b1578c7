"""Plan the carry from each of the paper's five starts to the default optimum (work in progress).

Usage: python experiments/tools/plan_paper_starts.py [START ...]   (1-5; default all)

Prints per start: the plan's reason (empty when planned), the grasp, the wall time, the number
of validity checks, the waypoints, the box path's length [m], the smallest robot-worker distance
[m] and the lift's range [m]. A figure, not a test.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from ergohandover.scene.planner import CarryPlanner
from ergohandover.scene.world import WorkerPosture, World
from ergohandover.study.baselines.comparison import PAPER_STARTS
from ergohandover.study.landscape.recorded import recorded_optimum
from ergohandover.twin.evaluate import Evaluator, evaluate, joint_angles, posture_solver

OPTIMUM = recorded_optimum(Path(__file__).resolve().parents[2] / "results")
"""The study's paper-score optimum, as results/landscape/stats.csv records it."""


def main() -> None:
    which = [int(a) for a in sys.argv[1:]] or [1, 2, 3, 4, 5]
    names = posture_solver(Evaluator()).model.joint_names
    posture = WorkerPosture(names, joint_angles(evaluate(OPTIMUM[None], joints=True))[0])
    with World() as world:
        planner = CarryPlanner(world, seed=0)
        for start in which:
            began, planner.checks = time.perf_counter(), 0
            plan = planner.plan(PAPER_STARTS[start - 1], OPTIMUM, posture)
            lifts = [w.lift for w in plan.waypoints] or [np.nan]
            print(f"start {start}: {plan.reason!r} grasp {plan.grasp} "
                  f"{time.perf_counter() - began:.1f} s, {planner.checks} checks, "
                  f"{len(plan.waypoints)} waypoints, {plan.length_m:.2f} m, clearance "
                  f"{plan.clearance_m:.3f} m, lift {min(lifts):.2f}-{max(lifts):.2f} m")


if __name__ == "__main__":
    main()
