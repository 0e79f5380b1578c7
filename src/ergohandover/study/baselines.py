"""Where to hand the box over: the paper's naive heuristic, the landscape's optimum, and their
comparison from a set of start points (the paper's Table "Comparison of Optimized and
Ergonomically Naive methods").

- :func:`shortest_distance`: the boundary point nearest the start (the paper's baseline,
  "the closest distance in the boundary so that the model can reasonably receive the box").
- :func:`optimised`: the landscape's best location for a score; among ties the most symmetric
  (the paper's symmetry reward picks it too).
- :func:`compare`: both locations for every start, with the twin's scores at exactly that
  location and whether the robot can carry the box there and hold it for the handover.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd

from ..errors import ConfigError
from ..landscape.cache import Landscape
from ..landscape.stats import optimum
from ..scene.robot import Reach, RobotSpec
from ..scene.world import CARRY_SPACING, Carry, WorkerPosture, World
from ..twin.evaluate import JOINT_PREFIX, Evaluator, evaluate, joint_angles, posture_solver
from ..twin.task import Boundary

# The paper's five start points (worker frame [m]) and its postural scores at the optimised
# and the shortest-distance location from each.
PAPER_STARTS = np.array([(0.028, 1.122, 1.354), (0.263, 1.122, 1.354), (-0.423, 1.122, 1.354),
                         (0.028, 0.472, 0.6), (0.028, 2.292, 1.354)])
PAPER_RESULTS = {"optimised": (4, 4, 4, 4, 4), "shortest_distance": (5, 6, 5, 7, 5)}
METHODS = ("optimised", "shortest_distance")
SCORES = ("paper_postural", "reba", "rula")


def shortest_distance(start: np.ndarray, boundary: Boundary) -> np.ndarray:
    """The point of the boundary nearest ``start``: the start clipped to the axis-aligned box
    (a start inside is returned unchanged).

    Args:
        start: (3,) or (N, 3) points, worker frame [m].
        boundary: the handover boundary.

    Returns:
        Same shape as ``start`` [m].
    """
    start = np.asarray(start, dtype=float)
    if start.shape[-1] != 3 or not np.isfinite(start).all():
        raise ConfigError(f"start must be finite points of shape (..., 3), got {start!r}")
    # Per axis, the nearest value of an interval is the clipped one, and the squared distance
    # is a sum over axes, so clipping each axis minimises it.
    return np.clip(start, boundary.lower, boundary.upper)


def optimised(landscape: Landscape, score: str = "paper_postural") -> np.ndarray:
    """The landscape's best feasible location for ``score``, the most symmetric among ties.

    Returns:
        (3,) worker frame [m].
    """
    return optimum(landscape, score)[1]


def paper_result(start: np.ndarray, method: str) -> float:
    """The paper's postural score for a start point of its table; NaN for any other start."""
    hit = np.flatnonzero(np.all(np.isclose(PAPER_STARTS, start, atol=5e-4), axis=1))
    return float(PAPER_RESULTS[method][hit[0]]) if hit.size else float("nan")


class Comparison(NamedTuple):
    """The comparison table (one row per start and method, start-major) and, per row, the
    robot's carry, its hold at the location on its own, and the twin's posture there."""

    table: pd.DataFrame
    carries: list[Carry]
    handovers: list[Reach]
    postures: list[WorkerPosture]


def compare(starts: np.ndarray, landscape: Landscape, evaluator: Evaluator | None = None,
            robot: RobotSpec | None = None, score: str = "paper_postural",
            spacing: float = CARRY_SPACING) -> Comparison:
    """Both handover locations for every start: the twin's scores there and the robot's
    feasibility of carrying the box there in a straight line and holding it.

    Args:
        starts: (S, 3) start points of the box, worker frame [m].
        landscape: the swept grid; its boundary is the shortest-distance boundary.
        evaluator: the worker and scoring (default: the landscape's defaults).
        robot: where the robot stands.
        score: the score the optimised location minimises.
        spacing: distance between carry samples [m].

    Returns:
        Columns: ``start_x, start_y, start_z, method, x, y, z, distance_m`` (start to
        location), the Evaluation columns at the location (``feasible``, ``reason``, every
        score, ...), ``paper_postural_paper`` (the paper's number, NaN for other starts),
        ``robot_feasible`` (0/1: the handover and every carry sample reachable),
        ``robot_reason`` (``handover: <reasons>`` if the robot cannot hold the box at the
        location at all, else which checks failed over which part of the carry, e.g.
        ``robot_ik 0-40%``), ``robot_handover`` (0/1: it can hold the box at the location,
        with any grasp), ``robot_error_m`` (the worse gripper's miss there [m]),
        ``carry_samples``.
    """
    evaluator = evaluator or Evaluator()
    starts = np.asarray(starts, dtype=float).reshape(-1, 3)
    best = optimised(landscape, score)
    rows = [(start, method, best if method == "optimised"
             else shortest_distance(start, landscape.grid.boundary))
            for start in starts for method in METHODS]
    locations = np.array([loc for _, _, loc in rows])
    # One solve per location: the table's scores and the posture the scene shows.
    scores = evaluate(locations, evaluator.body, evaluator.task, evaluator.solver,
                      evaluator.settings, evaluator.scoring, joints=True)
    names = posture_solver(evaluator).model.joint_names
    postures = [WorkerPosture(names, q) for q in joint_angles(scores)]
    scores = scores.drop(columns=[c for c in scores.columns if c.startswith(JOINT_PREFIX)])
    carries, handovers = [], []
    with World(evaluator.body, evaluator.task, robot) as world:
        for (start, _, location), posture in zip(rows, postures, strict=True):
            # The handover on its own (any grasp, fresh IK), then the carry that ends in it.
            handovers.append(world.reach(location, posture))
            carries.append(world.carry(start, location, posture, spacing))
    head = pd.DataFrame({
        "start_x": [r[0][0] for r in rows], "start_y": [r[0][1] for r in rows],
        "start_z": [r[0][2] for r in rows], "method": [r[1] for r in rows],
    })
    scores.insert(3, "distance_m", np.linalg.norm(locations - np.array([r[0] for r in rows]),
                                                  axis=1))
    table = pd.concat([head, scores], axis=1)
    table["paper_postural_paper"] = [paper_result(s, m) for s, m, _ in rows]
    table["robot_feasible"] = [int(h.reachable and c.reachable)
                               for h, c in zip(handovers, carries, strict=True)]
    table["robot_reason"] = [c.summary() if h.reachable else f"handover: {h.reason}"
                             for h, c in zip(handovers, carries, strict=True)]
    table["robot_handover"] = [int(h.reachable) for h in handovers]
    table["robot_error_m"] = [h.error_m for h in handovers]
    table["carry_samples"] = [len(c.samples) for c in carries]
    return Comparison(table, carries, handovers, postures)
