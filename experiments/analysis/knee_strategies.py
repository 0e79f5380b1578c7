"""Does the twin's cost have a squat in it? Solve low box locations from three whole-body
starting strategies — standing (stoop), semi-squat and squat — and print where each ends.

Usage: python experiments/analysis/knee_strategies.py [--iterations 200]

Each location is solved to convergence from each start with the default solver; the table
gives the final cost (the solver's own objective), the worse hand's error and the knee, hip,
lumbar and ankle angles. If every start ends in the same straight-legged posture at the same
cost, a semi-squat is not a local minimum of the cost: starting the solver elsewhere (a
lattice of strategies) cannot give a low box a human mix of knee and hip flexion, and the cost
itself needs a term that makes people bend their knees (the load on the lower back). A figure,
not a test.
"""

from __future__ import annotations

import argparse

import numpy as np

from ergohandover.study.validation import GAP_M  # the mean ankle-to-box gap people leave
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator, posture_solver
from ergohandover.twin.tasks import stack_tasks

# Starting strategies: joint -> angle [deg] on top of the solver's standing start.
STRATEGIES = {
    "standing (stoop)": {},
    "semi-squat": {"knee_flexion": 60, "hip_flexion": 60, "ankle_flexion": 15,
                   "lumbar_flexion": 20},
    "squat": {"knee_flexion": 110, "hip_flexion": 100, "ankle_flexion": 20,
              "lumbar_flexion": 20},
}
JOINTS = ("knee_flexion", "hip_flexion", "lumbar_flexion", "ankle_flexion")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=200)
    args = parser.parse_args()
    body = BodySpec()
    solver = posture_solver(Evaluator(body))
    model, weights = solver.model, solver.weights
    near = GAP_M + solver.task.box_depth / 2.0
    heights = (solver.task.box_height / 2.0, 0.30, body.segments().knee_height, 0.70, 0.90)
    locations = np.array([[0.0, y, near] for y in heights])
    targets = solver.targets(locations)
    half = solver.task.box_mass_kg / 2.0
    print(f"box centre {near:.3f} m in front of the ankles; {args.iterations} iterations")
    print(f"{'start':>17} {'height':>7} {'cost':>7} {'error':>6} "
          + " ".join(f"{j.split('_')[0]:>7}" for j in JOINTS) + "   [m, 1, cm, deg]")
    for name, angles in STRATEGIES.items():
        start = solver.standing.copy()
        for joint, deg in angles.items():
            start[model.index(joint)] = np.radians(deg)
        start = np.clip(start, model.lower, model.upper)
        solution = solver.iterate(locations, np.broadcast_to(start, (len(locations), model.nq)),
                                  args.iterations)
        _, res, w = stack_tasks(model.forward(solution.q), targets, weights, solver.sight,
                                solver.eye_cone, solver.support, weights.balance_margin,
                                {"left_grip": half, "right_grip": half})
        prefs = ((solution.q - solver.neutral) ** 2) @ solver.preference
        cost = 0.5 * ((res ** 2) @ w + prefs)
        for k, y in enumerate(heights):
            values = " ".join(f"{np.degrees(solution.q[k, model.index(j)]):7.1f}"
                              for j in JOINTS)
            print(f"{name:>17} {y:7.3f} {cost[k]:7.3f} {solution.hand_error[k] * 100:6.2f} "
                  f"{values}")


if __name__ == "__main__":
    main()
