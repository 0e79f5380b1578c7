"""Where to hand the box over: the paper's naive heuristic, the landscape's optimum, and their
comparison from a set of start points (the paper's Table "Comparison of Optimized and
Ergonomically Naive methods").

- :func:`shortest_distance`: the boundary point nearest the start (the paper's baseline,
  "the closest distance in the boundary so that the model can reasonably receive the box").
- :func:`optimised`: the landscape's best location for a score; among ties the most symmetric
  (the paper's symmetry reward picks it too).
- :func:`compare`: both locations for every start, with the twin's scores at exactly that
  location and the robot's carry of the box there, planned around every obstacle.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd
from tqdm import tqdm

from ...errors import ConfigError
from ...executor import Executor
from ...landscape import Landscape
from ...landscape.stats import optimum
from ...scene.carries import CarryJob, plan_carries
from ...scene.planner import DEFAULT_BUDGET, Plan
from ...scene.robot import RobotSpec
from ...scene.world import WorkerPosture
from ...twin.evaluate import JOINT_PREFIX, Evaluator, evaluate, joint_angles, posture_solver
from ...twin.task import Boundary

# The paper's five start points (worker frame [m]) and its postural scores at the optimised
# and the shortest-distance location from each.
PAPER_STARTS = np.array([(0.028, 1.122, 1.354), (0.263, 1.122, 1.354), (-0.423, 1.122, 1.354),
                         (0.028, 0.472, 0.6), (0.028, 2.292, 1.354)])
PAPER_RESULTS = {"optimised": (4, 4, 4, 4, 4), "shortest_distance": (5, 6, 5, 7, 5)}
METHODS = ("optimised", "shortest_distance")
SCORES = ("paper_postural", "reba", "rula")


# Starts "around the worker" for the robot's robustness check: on the robot's side, 1-2.3 m
# up, within 1.5 m of the worker's feet (horizontally) and at least 0.6 m in front of them.
REASONABLE = {"x": (-0.6, 0.6), "y": (1.0, 2.3), "z": (0.6, 1.5), "radius": 1.5}


def reasonable_starts(rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` start points drawn uniformly from :data:`REASONABLE` (worker frame [m])."""
    found = np.empty((0, 3))
    while len(found) < count:
        draw = rng.uniform([REASONABLE[a][0] for a in "xyz"], [REASONABLE[a][1] for a in "xyz"],
                           size=(4 * count, 3))
        found = np.vstack([found, draw[np.hypot(draw[:, 0], draw[:, 2])
                                        <= REASONABLE["radius"]]])
    return found[:count]


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
    robot's planned carry and the twin's posture at the location."""

    table: pd.DataFrame
    plans: list[Plan]
    postures: list[WorkerPosture]


def compare(starts: np.ndarray, landscape: Landscape, evaluator: Evaluator | None = None,
            robot: RobotSpec | None = None, score: str = "paper_postural", seed: int = 0,
            workers: int = 1, budget: int = DEFAULT_BUDGET,
            methods: tuple[str, ...] = METHODS,
            location: np.ndarray | None = None,
            executor: Executor | None = None) -> Comparison:
    """Both handover locations for every start: the twin's scores there and the robot's
    planned carry of the box there (:mod:`...scene.planner`).

    Args:
        starts: (S, 3) start points of the box, worker frame [m].
        landscape: the swept grid; its boundary is the shortest-distance boundary.
        evaluator: the worker and scoring (default: the landscape's defaults).
        robot: where the robot stands.
        score: the score the optimised location minimises.
        seed: spawns each carry's planning seed.
        workers: processes planning carries at a time.
        budget: robot poses checked per grasp before a carry is ``no_path``.
        methods: which of :data:`METHODS` to compare.
        location: the optimised location (x, y, z) [m], e.g. where a learner's run ended
            (default: the landscape's optimum, its most symmetric argmin).
        executor: where the carries are planned (an isolated one; default a local isolated
            pool of ``workers``).

    Returns:
        Columns: ``start_x, start_y, start_z, method, x, y, z, distance_m`` (start to
        location), the Evaluation columns at the location (``feasible``, ``reason``, every
        score, ...), ``paper_postural_paper`` (the paper's number, NaN for other starts),
        ``robot_feasible`` (0/1: the carry was planned), ``robot_reason`` (empty, or why not:
        one of :data:`~...scene.planner.PLAN_REASONS` and what failed), ``robot_handover``
        (0/1: the robot can hold the box at the location), ``planning_s``, ``path_length_m``
        (the box's path), ``waypoints``, ``clearance_m`` (the robot's smallest distance to the
        worker along the carry), ``checks`` (robot poses checked), ``grasp`` (approach yaw in
        degrees, ``flipped`` when the fingers close from below).
    """
    evaluator = evaluator or Evaluator()
    starts = np.asarray(starts, dtype=float).reshape(-1, 3)
    best = optimised(landscape, score) if location is None else np.asarray(location, float)
    rows = [(start, method, best if method == "optimised"
             else shortest_distance(start, landscape.grid.boundary))
            for start in starts for method in methods]
    locations = np.array([loc for _, _, loc in rows])
    # One solve per location: the table's scores and the posture the scene shows.
    scores = evaluate(locations, evaluator, joints=True)
    names = posture_solver(evaluator).model.joint_names
    postures = [WorkerPosture(names, q) for q in joint_angles(scores)]
    scores = scores.drop(columns=[c for c in scores.columns if c.startswith(JOINT_PREFIX)])
    jobs = [CarryJob(start, location, posture)
            for (start, _, location), posture in zip(rows, postures, strict=True)]
    # Planning takes seconds to a minute per carry: the bar says how far it is.
    plans = list(tqdm(plan_carries(jobs, evaluator.body, evaluator.task, robot, seed, workers,
                                   budget, executor),
                      total=len(jobs), desc="planning carries", unit="carry"))
    head = pd.DataFrame({
        "start_x": [r[0][0] for r in rows], "start_y": [r[0][1] for r in rows],
        "start_z": [r[0][2] for r in rows], "method": [r[1] for r in rows],
    })
    scores.insert(3, "distance_m", np.linalg.norm(locations - np.array([r[0] for r in rows]),
                                                  axis=1))
    table = pd.concat([head, scores], axis=1)
    table["paper_postural_paper"] = [paper_result(s, m) for s, m, _ in rows]
    table["robot_feasible"] = [int(plan.ok) for plan in plans]
    table["robot_reason"] = [plan.reason for plan in plans]
    table["robot_handover"] = [int(not plan.reason.startswith("unreachable_handover"))
                               for plan in plans]
    table["planning_s"] = [plan.planning_s for plan in plans]
    table["path_length_m"] = [plan.length_m for plan in plans]
    table["waypoints"] = [len(plan.waypoints) for plan in plans]
    table["clearance_m"] = [plan.clearance_m for plan in plans]
    table["checks"] = [plan.checks for plan in plans]
    table["grasp"] = [f"{plan.grasp[0]:g}{' flipped' if plan.grasp[1] else ''}"
                      for plan in plans]
    return Comparison(table, plans, postures)


def _cell(value, digits: int = 3) -> str:
    return "–" if pd.isna(value) else f"{value:.{digits}f}" if isinstance(value, float) \
        else str(value)


def markdown_table(table: pd.DataFrame) -> str:
    """One line per start: each method's location, scores (ours, the paper's) and robot."""
    head = ["start (x, y, z) [m]"]
    for method in ("optimised", "shortest distance"):
        head += [f"{method} (x, y, z) [m]", "postural: ours (paper)", "REBA", "RULA", "robot"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for _, group in table.groupby(["start_x", "start_y", "start_z"], sort=False):
        first = group.iloc[0]
        cells = [f"({first.start_x:.3f}, {first.start_y:.3f}, {first.start_z:.3f})"]
        for _, row in group.iterrows():
            ours = _cell(row.paper_postural) if row.feasible else f"infeasible ({row.reason})"
            paper = "" if pd.isna(row.paper_postural_paper) else \
                f" ({int(row.paper_postural_paper)})"
            robot = (f"yes: {row.path_length_m:.2f} m, {row.waypoints} waypoints, clearance "
                     f"{100 * row.clearance_m:.1f} cm, {row.planning_s:.1f} s"
                     if row.robot_feasible else f"no: {row.robot_reason}")
            cells += [f"({row.x:.3f}, {row.y:.3f}, {row.z:.3f})", ours + paper,
                      _cell(row.reba), _cell(row.rula), robot]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"
