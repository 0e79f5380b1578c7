"""Where does each whole-body strategy end for a low box, and which one does the twin keep?

Usage: python experiments/tools/knee_strategies.py [--iterations 200] [--percentile p50-male]

Boxes in front of the feet (the mean ankle-to-box gap people leave, Potvin & Bent 1997) from the
floor to elbow height are solved to convergence from each strategy of the solver's
``STRATEGY_DEG`` (stoop, semi-squat, squat). The table gives each one's final cost (the solver's
own objective), the worse hand's error, the knee, hip, lumbar and ankle angles and the postural
index (knee flexion / (ankle + hip + lumbar flexion); ~0 stoop, ~1 full squat, Burgess-Limerick
& Abernethy 1997). A star marks the strategy the warm-start lattice would keep: the first,
unless a later one is lower by more than ``STRATEGY_TIE``. Strategies that end in the same
posture share one basin of the cost. A figure, not a test.
"""

from __future__ import annotations

import argparse

import numpy as np

from ergohandover.study.validation.published import GAP_M
from ergohandover.twin.anthropometry import PERCENTILES, BodySpec
from ergohandover.twin.evaluate import Evaluator, posture_solver
from ergohandover.twin.solver import STRATEGY_TIE

JOINTS = ("knee_flexion", "hip_flexion", "lumbar_flexion", "ankle_flexion")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=200)
    parser.add_argument("--percentile", choices=list(PERCENTILES), default="p50-male")
    args = parser.parse_args()
    body = BodySpec.from_percentile(args.percentile)
    solver = posture_solver(Evaluator(body))
    model, seg = solver.model, body.segments()
    near = GAP_M + solver.task.box_depth / 2.0
    heights = (solver.task.box_height / 2.0, 0.30, seg.knee_height, 0.70,
               seg.shoulder_height - seg.upper_arm_length)
    locations = np.array([[0.0, y, near] for y in heights])
    runs = {}
    for name in solver.settings.strategies:
        start = np.broadcast_to(solver.strategy_start(name), (len(locations), model.nq))
        solution = solver.iterate(locations, start, args.iterations)
        runs[name] = (solution, solver.cost(locations, solution.q))
    # As the lattice keeps a node: the first strategy, unless a later one is clearly lower.
    costs = [cost for _, cost in runs.values()]
    best = np.zeros(len(locations), dtype=int)
    for s, cost in enumerate(costs[1:], start=1):
        best = np.where(cost < np.choose(best, costs) - STRATEGY_TIE, s, best)
    print(f"{args.percentile}: box centre {near:.3f} m in front of the ankles; "
          f"{args.iterations} iterations")
    print(f"{'start':>11} {'height':>7} {'cost':>7} {'error':>6} "
          + " ".join(f"{j.split('_')[0]:>7}" for j in JOINTS) + "   index  [m, 1, cm, deg, 1]")
    for k, y in enumerate(heights):
        for s, (name, (solution, cost)) in enumerate(runs.items()):
            deg = {j: np.degrees(solution.q[k, model.index(j)]) for j in JOINTS}
            bend = deg["ankle_flexion"] + deg["hip_flexion"] + deg["lumbar_flexion"]
            # Standing upright the index is 0/0: shown only once the body bends.
            index = f"{deg['knee_flexion'] / bend:5.2f}" if bend > 10.0 else "    -"
            mark = "*" if s == best[k] else " "
            print(f"{name:>10}{mark} {y:7.3f} {cost[k]:7.3f} {solution.hand_error[k] * 100:6.2f} "
                  + " ".join(f"{deg[j]:7.1f}" for j in JOINTS) + f"   {index}")


if __name__ == "__main__":
    main()
