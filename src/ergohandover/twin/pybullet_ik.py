"""PyBullet's own inverse kinematics for the twin, for comparison with the whole-body solver.

``calculateInverseKinematics2`` puts both grip points on their handles. A single call from a
standing pose rarely converges (it is a few damped steps), so it is called repeatedly from
its own answer, clipped to the joint limits each time, until both hands are within
``tolerance`` or ``calls`` run out. No null-space arguments are passed: with them PyBullet's IK
does not move the hands. It knows nothing of balance, gaze or palm orientation, so its postures
are what a generic IK gives, not what a person would do.
"""

from __future__ import annotations

import os

import numpy as np

from ..sim import connect_direct
from ..sim import pybullet as _pybullet
from .anthropometry import BodySpec
from .kinematics import KinematicModel
from .skeleton import build_skeleton
from .solver import START_POSTURE_DEG, Solution, handover_targets, support_rectangle
from .task import TaskSpec
from .tasks import Targets
from .urdf import load_worker


class PyBulletSolver:
    """Postures from PyBullet's IK, one location at a time (same interface as PostureSolver).

    Args:
        body: the worker.
        task: the box and its handles.
        calls: most IK calls per location.
        tolerance: stop once both grips are this close to their handles [m].
    """

    def __init__(self, body: BodySpec | None = None, task: TaskSpec | None = None,
                 calls: int = 30, tolerance: float = 1e-3):
        self.body, self.task = body or BodySpec(), task or TaskSpec()
        self.calls, self.tolerance = calls, tolerance
        self.model = KinematicModel(build_skeleton(self.body))
        self.support = support_rectangle(self.body)
        self._pid = None

    def _connect(self) -> None:
        """One DIRECT client per process (a forked worker must not share its parent's)."""
        if self._pid == os.getpid():
            return
        pybullet = self.pybullet = _pybullet()
        self.client = connect_direct()
        self.worker = load_worker(self.client, self.body)
        info = [pybullet.getJointInfo(self.worker.body_id, i, physicsClientId=self.client)
                for i in range(pybullet.getNumJoints(self.worker.body_id,
                                                     physicsClientId=self.client))]
        # PyBullet returns IK answers for its movable joints in index order.
        self.pb_names = [i[1].decode() for i in info if i[2] != pybullet.JOINT_FIXED]
        self.order = np.array([self.model.index(n) for n in self.pb_names])
        self.standing = np.zeros(self.model.nq)
        for name in self.model.joint_names:
            base = name.removeprefix("left_").removeprefix("right_")
            self.standing[self.model.index(name)] = np.radians(START_POSTURE_DEG.get(base, 0.0))
        self._pid = os.getpid()

    def targets(self, locations: np.ndarray) -> Targets:
        return handover_targets(self.task, locations)

    def _set(self, q: np.ndarray) -> None:
        pybullet = self.pybullet
        for name in self.pb_names:
            pybullet.resetJointState(self.worker.body_id, self.worker.joints[name],
                                     q[self.model.index(name)], physicsClientId=self.client)

    def _solve_one(self, left: np.ndarray, right: np.ndarray) -> np.ndarray:
        body, links, pybullet = self.worker.body_id, self.worker.links, self.pybullet
        q = self.standing.copy()
        self._set(q)
        for _ in range(self.calls):
            answer = pybullet.calculateInverseKinematics2(
                body, [links["left_grip"], links["right_grip"]], [left.tolist(), right.tolist()],
                maxNumIterations=50, residualThreshold=1e-5, physicsClientId=self.client)
            q[self.order] = answer
            q = np.clip(q, self.model.lower, self.model.upper)
            self._set(q)
            state = self.model.forward(q[None])
            error = max(np.linalg.norm(state.point("left_grip")[0] - left),
                        np.linalg.norm(state.point("right_grip")[0] - right))
            if error < self.tolerance:
                break
        return q

    def solve(self, locations: np.ndarray) -> Solution:
        """Postures for box centres at ``locations`` (N, 3), worker frame [m]."""
        self._connect()
        locations = np.asarray(locations, dtype=float).reshape(-1, 3)
        targets = self.targets(locations)
        q = np.array([self._solve_one(lt, rt) for lt, rt in zip(targets.left, targets.right,
                                                                 strict=True)])
        q = q.reshape(-1, self.model.nq)
        state = self.model.forward(q)
        half = self.task.box_mass_kg / 2.0
        error = np.maximum(np.linalg.norm(state.point("left_grip") - targets.left, axis=1),
                           np.linalg.norm(state.point("right_grip") - targets.right, axis=1))
        com = state.com({"left_grip": half, "right_grip": half})
        return Solution(q, error, com, state)
