"""Planned carries: several at once, each in a process of its own; their path files; and the
replay of a path file in plain PyBullet.

- :func:`plan_carries`: a :class:`~.planner.Plan` per :class:`CarryJob`. OMPL takes one random
  seed per process, so each plan runs in a new process with its own seed (spawned from the one
  given): a plan is a function of its job and that seed, whatever else runs.
- :func:`path_table`: one row per waypoint: ``time`` [s], the box pose (``box_x, box_y, box_z``
  [m] and ``box_qx, box_qy, box_qz, box_qw``, worker frame), one column per movable joint of the
  robot's URDF (named as there: the drive and lift [m], the arms and fingers [rad]); the first
  row also holds the robot base's pose (``base_x, base_y, base_z`` [m], ``base_yaw`` [rad],
  PyBullet's world frame).
- :func:`replay`: a path file played in a new PyBullet client from a robot URDF: the deepest
  self-penetration and the largest joint step between consecutive waypoints.
"""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd

from ..errors import ConfigError
from ..executor import Executor, LocalExecutor
from ..frames import rotation_to_worker
from ..sim import connect_direct
from ..sim import pybullet as _pybullet
from .planner import DEFAULT_BUDGET, CarryPlanner, Plan
from .robot import matrix_to_quaternion
from .robot_collision import deepest_self_penetration, self_collision_pairs
from .robot_urdf import resolve_packages
from .world import WorkerPosture, World

BOX_COLUMNS = ("box_x", "box_y", "box_z", "box_qx", "box_qy", "box_qz", "box_qw")
BASE_COLUMNS = ("base_x", "base_y", "base_z", "base_yaw")


class CarryJob(NamedTuple):
    """A carry to plan: from ``start`` to the handover at ``location`` (worker frame (3,) [m]),
    where the worker takes ``posture`` (None: it stays at rest)."""

    start: np.ndarray
    location: np.ndarray
    posture: WorkerPosture | None = None


def plan_seeds(seed: int, count: int) -> list[int]:
    """The OMPL seed of each of ``count`` plans, spawned from ``seed``."""
    return [int(s.generate_state(1)[0] % 2**31)
            for s in np.random.SeedSequence(seed).spawn(count)]


def plan_carries(jobs: Sequence[CarryJob], body=None, task=None, robot=None, seed: int = 0,
                 workers: int = 1, budget: int = DEFAULT_BUDGET,
                 executor: Executor | None = None) -> Iterator[Plan]:
    """Plan every job, each in a new process; yields the plans in job order.

    Args:
        jobs: the carries.
        body, task, robot: the scene (defaults: :class:`~.world.World`'s).
        seed: spawns each plan's OMPL seed (:func:`plan_seeds`).
        workers: processes at a time (when no ``executor`` is given).
        budget: robot poses checked per grasp (see :class:`~.planner.CarryPlanner`).
        executor: an *isolated* executor (a fresh process per job, as OMPL takes one seed per
            process), e.g. a Ray one; default a local isolated pool of ``workers``.
    """
    seeds = plan_seeds(seed, len(jobs))
    args = [(job, body, task, robot, s, budget) for job, s in zip(jobs, seeds, strict=True)]
    if executor is not None and not getattr(executor, "isolated", False):
        raise ConfigError("executor: carries need an isolated executor (a process per carry: "
                          "OMPL takes one seed per process)")
    with executor or LocalExecutor(workers, isolated=True) as pool:
        yield from pool.map(_plan_one, args)


def _plan_one(args) -> Plan:
    job, body, task, robot, seed, budget = args
    with World(body, task, robot) as world:
        return CarryPlanner(world, seed, budget).plan(job.start, job.location, job.posture)


def path_table(world: World, plan: Plan) -> pd.DataFrame:
    """The plan's waypoints as a table (see the module doc); leaves the robot at the last."""
    p, c, robot = world.p, world.client, world.robot
    rows = []
    for w in plan.waypoints:
        world.bring_robot(w.location, w.lift)
        for arm, q in w.q.items():
            robot.set_arm(arm, q)
        turn = p.getBasePositionAndOrientation(world.box.body_id, physicsClientId=c)[1]
        matrix = np.array(p.getMatrixFromQuaternion(turn)).reshape(3, 3)
        quaternion = matrix_to_quaternion(rotation_to_worker(matrix))
        rows.append({"time": w.time, **dict(zip(BOX_COLUMNS, [*w.location, *quaternion],
                                                strict=True)), **robot.joint_values()})
    table = pd.DataFrame(rows)
    at, turn = p.getBasePositionAndOrientation(robot.body, physicsClientId=c)
    base = [*at, p.getEulerFromQuaternion(turn)[2]]
    for k, name in enumerate(BASE_COLUMNS):
        table.insert(1 + len(BOX_COLUMNS) + k, name, [base[k]] + [math.nan] * (len(table) - 1))
    return table


class Replay(NamedTuple):
    """What a path file does to the robot of a URDF: the deepest penetration between two of
    its links [m], the largest step of a revolute joint [rad] and of a prismatic one [m]
    between consecutive waypoints."""

    self_penetration_m: float
    revolute_step_rad: float
    prismatic_step_m: float


def replay(table: pd.DataFrame, urdf: str | os.PathLike) -> Replay:
    """Play a path table (from :func:`path_table` or its CSV) on the robot of ``urdf`` (its
    ``package://franka_panda/`` meshes resolved to the installed pybullet_data) in a new
    DIRECT client: every joint set by name at every waypoint."""
    p = _pybullet()
    with tempfile.NamedTemporaryFile("w", suffix=".urdf", delete=False) as handle:
        handle.write(resolve_packages(Path(urdf).read_text()))
    client = connect_direct()
    try:
        first = table.iloc[0]
        body = p.loadURDF(handle.name, [first.base_x, first.base_y, first.base_z],
                          p.getQuaternionFromEuler([0.0, 0.0, first.base_yaw]),
                          useFixedBase=True, physicsClientId=client)
        joints = {}
        for i in range(p.getNumJoints(body, physicsClientId=client)):
            info = p.getJointInfo(body, i, physicsClientId=client)
            if info[1].decode() in table.columns:
                joints[info[1].decode()] = (i, info[2])
        pairs = self_collision_pairs(p, body, client)
        deepest = 0.0
        for _, row in table.iterrows():
            for name, (index, _) in joints.items():
                p.resetJointState(body, index, float(row[name]), physicsClientId=client)
            deepest = max(deepest, deepest_self_penetration(p, body, pairs, client))
    finally:
        p.disconnect(client)
        os.unlink(handle.name)
    steps = table[list(joints)].diff().abs().max()
    kinds = {name: kind for name, (_, kind) in joints.items()}
    revolute = [steps[n] for n, k in kinds.items() if k == p.JOINT_REVOLUTE]
    prismatic = [steps[n] for n, k in kinds.items() if k == p.JOINT_PRISMATIC]
    return Replay(deepest, float(max(revolute, default=0.0)),
                  float(max(prismatic, default=0.0)))
