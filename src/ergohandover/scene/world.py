"""The PyBullet scene of a handover: the worker, the dual-arm robot and the box, and the carry
of the box along a straight line from a start point to the handover location.

Positions given to and returned by this module are in the worker frame (x right, y up,
z forward; metres); the scene itself lives in PyBullet's world frame (:mod:`frames`).
The box is moved kinematically (it is level and never simulated); the robot holds it by its
``{side}_robot_grasp`` frames; the worker stands at rest (arms hanging) while the box travels
and takes its solved posture (from the posture solver) at the handover.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from ..frames import worker_to_world
from ..sim import connect_direct
from ..sim import pybullet as _pybullet
from ..twin.anthropometry import BodySpec
from ..twin.task import TaskSpec
from ..twin.urdf import load_worker
from .box import HANDLE_RADIUS, load_box
from .robot import ARMS, GRASPS, DualArmRobot, Reach, RobotSpec

CARRY_SPACING = 0.05  # distance between samples along a carry [m]
# Largest joint motion between two carry samples [rad]: at 5 cm spacing, 0.5 rad is ten
# times what a joint needs to follow the box smoothly, yet far below a configuration flip.
MAX_JOINT_STEP_RAD = 0.5


class WorkerPosture(NamedTuple):
    """The worker's joint angles [rad] by name (e.g. ``posture_solver(...).model.joint_names``
    and one row of ``.solve(locations).q``)."""

    joint_names: Sequence[str]
    q: np.ndarray


class CarrySample(NamedTuple):
    """One box pose along a carry: how far along (0 = start, 1 = handover), the box centre
    (3,) [m] in the worker frame, and whether the robot can hold it there."""

    fraction: float
    location: np.ndarray
    reach: Reach


class Carry(NamedTuple):
    """Every sample of a carry, start first; the last one is the handover."""

    samples: list[CarrySample]

    @property
    def reachable(self) -> bool:
        """The robot can hold the box at every sample, the handover included."""
        return all(s.reach.reachable for s in self.samples)

    @property
    def reachable_count(self) -> int:
        return sum(s.reach.reachable for s in self.samples)

    @property
    def handover(self) -> Reach:
        return self.samples[-1].reach

    def summary(self) -> str:
        """Empty when reachable; else which reasons, over which part of the path, e.g.
        ``robot_ik 0-40%``."""
        spans: dict[str, list[float]] = {}
        for s in self.samples:
            for reason in filter(None, s.reach.reason.split(";")):
                spans.setdefault(reason, []).append(s.fraction)
        return "; ".join(f"{r} {100 * min(f):.0f}-{100 * max(f):.0f}%" for r, f in spans.items())


class World:
    """One DIRECT PyBullet client holding the worker, the robot and the box.

    Use as a context manager (or call :meth:`close`): the client is always disconnected.

    Args:
        body: the worker; default the ANSUR II 50th-percentile man.
        task: the box; default :class:`TaskSpec`.
        robot: where the robot stands; default :class:`RobotSpec`.
    """

    def __init__(self, body: BodySpec | None = None, task: TaskSpec | None = None,
                 robot: RobotSpec | None = None):
        self.p = _pybullet()
        self.body, self.task = body or BodySpec(), task or TaskSpec()
        self.client = connect_direct()
        try:
            self.worker = load_worker(self.client, self.body)
            self.box = load_box(self.client, self.task)
            self.robot = DualArmRobot(self.client, robot)
            self.robot.open_fingers(HANDLE_RADIUS)
        except BaseException:
            self.close()
            raise

    def close(self) -> None:
        if self.p.isConnected(self.client):
            self.p.disconnect(self.client)

    def __enter__(self) -> World:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def place_box(self, location: np.ndarray) -> None:
        """Put the box's centre at ``location`` (3,) [m], worker frame, level and square."""
        self.p.resetBasePositionAndOrientation(
            self.box.body_id, worker_to_world(location).tolist(), [0, 0, 0, 1],
            physicsClientId=self.client)

    def pose_worker(self, posture: WorkerPosture | None = None) -> None:
        """Set the worker's joints by name; ``None``: standing at rest (every joint 0)."""
        angles = dict.fromkeys(self.worker.joints, 0.0)
        if posture is not None:
            angles.update(zip(posture.joint_names, map(float, posture.q), strict=True))
        for name, angle in angles.items():
            self.p.resetJointState(self.worker.body_id, self.worker.joints[name], angle,
                                   physicsClientId=self.client)

    def grasp_targets(self) -> dict[str, np.ndarray]:
        """Each arm's grasp point on the box as placed, world frame [m] (the ``left`` arm
        holds the handle in the worker's left hand)."""
        return {arm: np.array(self.p.getLinkState(
                    self.box.body_id, self.box.links[f"{arm}_robot_grasp"],
                    computeForwardKinematics=True, physicsClientId=self.client)[4])
                for arm in ARMS}

    def reach(self, location: np.ndarray, posture: WorkerPosture | None = None,
              grasps: list[tuple[float, bool]] | None = None,
              seed: dict[str, np.ndarray] | None = None) -> Reach:
        """Can the robot hold the box at ``location`` (worker frame [m]) with the worker in
        ``posture`` (default: at rest)? Leaves the scene in that pose.

        Args:
            location: the box centre (3,) [m], worker frame.
            posture: the worker's posture (default: at rest).
            grasps: the grasps to try (default: all, see :meth:`DualArmRobot.reach`).
            seed: arm -> joint angles (7,) [rad] to start the IK from (default: rest pose).
        """
        self.place_box(np.asarray(location, dtype=float))
        self.pose_worker(posture)
        return self.robot.reach(self.grasp_targets(), self.box.body_id, self.worker.body_id,
                                grasps, seed)

    def _path(self, points: list[tuple[float, np.ndarray]], posture: WorkerPosture | None,
              grasp: tuple[float, bool], backward: bool) -> Carry:
        """One grasp along the sampled path, each IK seeded by the previous sample's pose;
        ``backward``: solved from the handover back to the start (reported start first)."""
        order = list(range(len(points)))[::-1] if backward else list(range(len(points)))
        samples: dict[int, CarrySample] = {}
        seed, previous_ok = None, False
        for i in order:
            fraction, point = points[i]
            reach = self.reach(point, posture if i == len(points) - 1 else None, [grasp], seed)
            if previous_ok and reach.reachable and max(
                    np.abs(reach.q[a] - seed[a]).max() for a in ARMS) > MAX_JOINT_STEP_RAD:
                reach = reach._replace(reachable=False, reason="robot_discontinuous")
            samples[i] = CarrySample(fraction, point, reach)
            seed, previous_ok = reach.q, reach.reachable
        return Carry([samples[i] for i in range(len(points))])

    def carry(self, start: np.ndarray, location: np.ndarray,
              posture: WorkerPosture | None = None,
              spacing: float = CARRY_SPACING) -> Carry:
        """Carry the box in a straight line from ``start`` to ``location`` (worker frame [m]).

        Samples every ``spacing`` metres at most (both ends included). The box is held with
        one grasp all the way (the robot cannot let go mid-carry): each grasp of
        :data:`robot.GRASPS` is tried in turn, solved from the handover back to the start and
        then forward, and the first that reaches every sample is kept, else the best (ending
        in the handover, then reaching most samples). Along a path each sample's IK starts from the
        previous pose, and a joint moving more than :data:`MAX_JOINT_STEP_RAD` between two
        samples makes the later one ``robot_discontinuous`` (the IK jumped to another
        configuration, which the straight carry cannot pass through). The worker stands at
        rest until the last sample, where it takes ``posture`` (its grip on the handles).

        Returns:
            Every sample with its reachability.
        """
        start, location = np.asarray(start, float), np.asarray(location, float)
        n = max(2, math.ceil(np.linalg.norm(location - start) / spacing) + 1)
        points = [(float(f), start + f * (location - start)) for f in np.linspace(0, 1, n)]
        best = None
        for grasp, backward in itertools.product(GRASPS, (True, False)):
            carry = self._path(points, posture, grasp, backward)
            # Prefer a carry that ends in the handover, then the one reaching most samples.
            rank = (carry.handover.reachable, carry.reachable_count)
            if best is None or rank > (best.handover.reachable, best.reachable_count):
                best = carry
            if carry.reachable:
                break
        return best
