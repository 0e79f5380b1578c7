"""The PyBullet scene of a handover: the worker, the dual-arm robot and the box.

Positions given to and returned by this module are in the worker frame (x right, y up,
z forward; metres); the scene itself lives in PyBullet's world frame (:mod:`frames`).
The box is moved kinematically (it is level and never simulated); the robot holds it by its
``{side}_robot_grasp`` frames, its base driven to keep the box at arm's length; the worker
stands at rest (arms hanging) while the box travels and takes its solved posture (from the
posture solver) at the handover. The carries themselves are planned in :mod:`.planner`.

The client is headless (DIRECT) unless a ``World(gui=True)`` asks for PyBullet's own window, which
needs a display (:func:`~ergohandover.sim.connect_gui`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from ..frames import worker_to_world
from ..sim import connect_direct, connect_gui, wait_while_open
from ..sim import pybullet as _pybullet
from ..twin.anthropometry import BodySpec
from ..twin.task import TaskSpec
from ..twin.urdf import load_worker
from .box import HANDLE_RADIUS, load_box
from .robot import ARMS, DualArmRobot, Reach, RobotSpec

HOLD_LIFTS = 6  # lifts tried by World.hold_at_some_lift, evenly from 0 to the lift's travel


class WorkerPosture(NamedTuple):
    """The worker's joint angles [rad] by name (e.g. ``posture_solver(...).model.joint_names``
    and one row of ``.solve(locations).q``)."""

    joint_names: Sequence[str]
    q: np.ndarray


class World:
    """One PyBullet client holding the worker, the robot and the box.

    Use as a context manager (or call :meth:`close`): the client is always disconnected.

    Args:
        body: the worker; default the ANSUR II 50th-percentile man.
        task: the box; default :class:`TaskSpec`.
        robot: where the robot stands; default :class:`RobotSpec`.
        gui: show the scene in PyBullet's own window (needs a display, else
            :class:`~ergohandover.sim.NoDisplayError`); default headless (DIRECT).
    """

    def __init__(self, body: BodySpec | None = None, task: TaskSpec | None = None,
                 robot: RobotSpec | None = None, gui: bool = False):
        self.p = _pybullet()
        self.body, self.task = body or BodySpec(), task or TaskSpec()
        self.gui = gui
        self.client = connect_gui() if gui else connect_direct()
        try:
            if gui:  # the scene alone: PyBullet's side panels would cover half of it
                self.p.configureDebugVisualizer(self.p.COV_ENABLE_GUI, 0,
                                                physicsClientId=self.client)
            self.worker = load_worker(self.client, self.body)
            self.box = load_box(self.client, self.task)
            self.robot = DualArmRobot(self.client, robot)
            self.robot.open_fingers(HANDLE_RADIUS)
        except BaseException:
            self.close()
            raise

    def close(self) -> None:
        if self.connected:
            self.p.disconnect(self.client)

    @property
    def connected(self) -> bool:
        """False once closed, or once the user closed the GUI window."""
        return bool(self.p.isConnected(self.client))

    def look_at(self, eye, target) -> None:
        """Point the GUI window's camera from ``eye`` toward ``target`` (world frame [m]), as
        :meth:`~.scene_render.SceneRenderer.view` looks; nothing in a headless world."""
        if not self.gui:
            return
        offset = np.asarray(eye, dtype=float) - np.asarray(target, dtype=float)
        distance = float(np.linalg.norm(offset))
        # PyBullet's camera sits at yaw 0 on -y of its target, pitch negative looking down.
        yaw = float(np.degrees(np.arctan2(offset[0], -offset[1])))
        pitch = -float(np.degrees(np.arcsin(offset[2] / distance)))
        self.p.resetDebugVisualizerCamera(distance, yaw, pitch, list(target),
                                          physicsClientId=self.client)

    def wait_until_closed(self) -> None:
        """Return when the user closes the GUI window or presses Ctrl-C (at once when
        headless)."""
        if self.gui:
            wait_while_open(self.client)

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

    def bring_robot(self, location: np.ndarray, lift: float | None = None) -> None:
        """Place the box at ``location`` (worker frame [m]) and the robot's base where it holds
        a box there: driven to keep it at arm's length (:meth:`DualArmRobot.drive_for`), the
        lift at ``lift`` [m] (default: where it is)."""
        location = np.asarray(location, dtype=float)
        self.place_box(location)
        robot = self.robot
        robot.set_base(robot.lift if lift is None else lift,
                       robot.drive_for(float(worker_to_world(location)[0])))

    def reach(self, location: np.ndarray, posture: WorkerPosture | None = None,
              grasps: list[tuple[float, bool]] | None = None,
              seed: dict[str, np.ndarray] | None = None, lift: float | None = None) -> Reach:
        """Can the robot hold the box at ``location`` (worker frame [m]) with the worker in
        ``posture`` (default: at rest)? The base drives to keep the box at arm's length
        (:meth:`bring_robot`). Leaves the scene in that pose.

        Args:
            location: the box centre (3,) [m], worker frame.
            posture: the worker's posture (default: at rest).
            grasps: the grasps to try (default: all, see :meth:`DualArmRobot.reach`).
            seed: arm -> joint angles (7,) [rad] to start the IK from (default: rest pose).
            lift: the lift [m] (default: where it is).
        """
        self.bring_robot(location, lift)
        self.pose_worker(posture)
        return self.robot.reach(self.grasp_targets(), self.box.body_id, self.worker.body_id,
                                grasps, seed)

    def hold_pose(self, location: np.ndarray,
                  posture: WorkerPosture | None = None) -> tuple[dict[str, np.ndarray], float]:
        """The robot's arms (arm -> joint angles (7,) [rad]) and lift [m] holding the box at
        ``location`` (worker frame [m]) with the worker in ``posture``: the hold of
        :meth:`hold_at_some_lift`, else the lowest lift's attempt (a picture still shows the
        robot reaching)."""
        reach, lift = self.hold_at_some_lift(location, posture)
        return reach.q, lift

    def hold_at_some_lift(self, location: np.ndarray,
                          posture: WorkerPosture | None = None) -> tuple[Reach, float]:
        """The first lift (of :data:`HOLD_LIFTS`, lowest first) at which the robot holds the
        box at ``location`` (worker frame [m]) with the worker in ``posture``, and that hold;
        when none does, the lowest lift's attempt (its reason says why) and that lift [m]."""
        first = None
        for lift in np.linspace(0.0, self.robot.spec.lift_range, HOLD_LIFTS):
            reach = self.reach(location, posture, lift=float(lift))
            if reach.reachable:
                return reach, float(lift)
            first = first or (reach, float(lift))
        return first
