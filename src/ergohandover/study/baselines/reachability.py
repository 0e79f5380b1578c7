"""Where can the robot hold the box for the handover? Over a grid of the landscape's boundary,
and for the landscape's best locations in turn until one is held.

At each location the twin takes its solved posture (gripping the handles) and the robot tries
to hold the box there with any grasp at six lifts from 0 to the lift's travel, lowest first
(:meth:`~...scene.world.World.hold_at_some_lift`; its base driven to keep the box at arm's
length): PyBullet's IK within the tolerances, inside the joint limits, touching neither
itself, the box nor the worker (:meth:`~...scene.world.World.reach`). The first lift that
holds is kept, with the robot's smallest distance to the worker there.

- :func:`reachability`: a boundary's grid, one row per location.
- :func:`restricted_optimum`: the landscape's feasible locations in order of score (the most
  symmetric first among equal scores, as :func:`~...landscape.stats.optimum` picks) until the
  robot holds one: the best handover the robot can serve, beside the unrestricted optimum.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd

from ...executor import LocalExecutor
from ...landscape import Landscape
from ...landscape.grid import Grid
from ...landscape.stats import most_symmetric, optimum
from ...scene.robot import RobotSpec
from ...scene.robot_collision import clearance
from ...scene.world import WorkerPosture, World
from ...twin.evaluate import Evaluator, evaluate, joint_angles, posture_solver
from ...twin.task import Boundary

REACH_STEP = 0.04  # the reachability grid's step [m]
CHUNK = 64  # locations per job
MAX_CANDIDATES = 512  # best locations tried for the restricted optimum
BATCH = 16  # of them at a time


class RestrictedOptimum(NamedTuple):
    """The landscape's best location (the unrestricted optimum) and the best the robot can
    hold: their scores and locations (worker frame [m]); ``rank``: how many locations of the
    landscape were tried (1: the optimum itself is held); NaN location when none was."""

    score: str
    best: float
    best_location: np.ndarray
    held: float
    held_location: np.ndarray
    rank: int


def _hold(world: World, location, posture) -> tuple[int, str, float, float]:
    """(held, reason, lift, clearance) at one location."""
    reach, lift = world.hold_at_some_lift(location, posture)
    if not reach.reachable:
        return 0, reach.reason, float("nan"), float("nan")
    return 1, "", lift, clearance(world.p, world.robot.body, world.worker.body_id,
                                  world.client)


def _hold_chunk(args) -> list[tuple[int, str, float, float]]:
    evaluator, robot, names, locations, postures = args
    with World(evaluator.body, evaluator.task, robot) as world:
        return [_hold(world, location, WorkerPosture(names, q))
                for location, q in zip(locations, postures, strict=True)]


def holds(locations: np.ndarray, evaluator: Evaluator | None = None,
          robot: RobotSpec | None = None, workers: int = 1) -> pd.DataFrame:
    """The robot's hold at each location (N, 3) with the twin in its posture there.

    Returns:
        Columns ``x, y, z, twin_feasible, paper_postural, held`` (0/1), ``reason`` (the first
        lift's failure when none holds), ``lift_m``, ``clearance_m`` (robot to worker).
    """
    evaluator = evaluator or Evaluator()
    locations = np.asarray(locations, dtype=float).reshape(-1, 3)
    scores = evaluate(locations, evaluator, joints=True, workers=workers)
    names = posture_solver(evaluator).model.joint_names
    postures = joint_angles(scores)
    jobs = [(evaluator, robot, names, locations[i:i + CHUNK], postures[i:i + CHUNK])
            for i in range(0, len(locations), CHUNK)]
    with LocalExecutor(workers) as executor:
        held = [row for chunk in executor.map(_hold_chunk, jobs) for row in chunk]
    table = pd.DataFrame(locations, columns=["x", "y", "z"])
    table["twin_feasible"] = scores["feasible"].astype(int).to_numpy()
    table["paper_postural"] = scores["paper_postural"].to_numpy()
    table[["held", "reason", "lift_m", "clearance_m"]] = pd.DataFrame(held)
    return table


def reachability(boundary: Boundary, evaluator: Evaluator | None = None,
                 robot: RobotSpec | None = None, step: float = REACH_STEP,
                 workers: int = 1) -> pd.DataFrame:
    """:func:`holds` over a boundary every ``step`` [m]."""
    return holds(Grid(boundary, step).points(), evaluator, robot, workers)


def restricted_optimum(landscape: Landscape, evaluator: Evaluator | None = None,
                       robot: RobotSpec | None = None, score: str = "paper_postural",
                       workers: int = 1) -> RestrictedOptimum:
    """The best location the robot can hold (see the module doc)."""
    cells, best_location = optimum(landscape, score)
    values = landscape.arrays[score]
    feasible = np.flatnonzero(landscape.feasible)
    tried = 0
    # Score levels from the lowest; within a level, the most symmetric first; a few
    # candidates at a time, so that the search stops soon after the first hold.
    for level in np.unique(values[feasible]):
        points = landscape.grid.coordinates(feasible[values[feasible] == level])
        points = points[_symmetric_order(points)]
        for i in range(0, len(points), BATCH):
            if tried >= MAX_CANDIDATES:
                return RestrictedOptimum(score, float(values[cells[0]]), best_location,
                                         float("nan"), np.full(3, np.nan), tried)
            batch = points[i:i + BATCH]
            hit = np.flatnonzero(holds(batch, evaluator, robot, workers)["held"].to_numpy())
            if hit.size:
                return RestrictedOptimum(score, float(values[cells[0]]), best_location,
                                         float(level), batch[hit[0]], tried + int(hit[0]) + 1)
            tried += len(batch)
    return RestrictedOptimum(score, float(values[cells[0]]), best_location, float("nan"),
                             np.full(3, np.nan), tried)


def _symmetric_order(points: np.ndarray) -> np.ndarray:
    """Indices of ``points`` from the most symmetric (as :func:`most_symmetric` picks) on:
    the pick first, then by |x| and distance to the pick."""
    first = most_symmetric(points)
    distance = np.linalg.norm(points - points[first], axis=1)
    order = np.lexsort((distance, np.round(np.abs(points[:, 0]), 9)))
    return np.concatenate([[first], order[order != first]])
