"""The dual-arm robot: two 7-DOF Franka Panda arms on a stand with a vertical lift, on a mobile
base that drives toward the worker; both arms face the worker.

The robot is one body loaded from its URDF (:mod:`.robot_urdf`: the mobile base, the stand, the
lift, and the arms from pybullet_data's ``franka_panda/panda.urdf``, Apache-2.0, see
``urdf/README.md``). Seen from the worker (world frame: the worker at the origin facing +x,
left = +y), the arm bases stand ``distance`` in front of the worker's feet less the drive,
``arm_spacing`` apart, at ``mount_height`` plus the lift (:meth:`DualArmRobot.set_base`).
PyBullet's IK for each arm runs on a plain Panda placed :data:`IK_OFFSET` below at that arm's
base pose, and its answer is set on the robot. The ``left`` arm (at +y) holds the handle in
the worker's left hand, the ``right`` arm the other one. See ``docs/robot.md`` for why the
defaults are what they are.

The box is held level by both grippers at its ``{side}_robot_grasp`` frames (see
:mod:`.box`). The fingers close vertically on the horizontal rail, so any
approach direction in the horizontal plane grips it: a grasp is an approach yaw, from straight
in from the side (0°) turning toward the robot (:data:`APPROACH_YAWS_DEG`), with the fingers
one way up or the other (:data:`GRASPS`).

Reachability of a box pose, with the first failing check as the reason (:data:`REASONS`):
PyBullet's ``calculateInverseKinematics`` (null-space limits and rest pose, called repeatedly
from its own answer) must put each grasp frame within ``position_tolerance`` of its handle and
within ``angle_tolerance_deg`` of the level-box orientation (``robot_ik``) without a joint
beyond its limit (``robot_joint_limit``: only a pose beyond a limit reaches); then no link may
penetrate another non-adjacent link of the robot or the stand (``robot_collision_self``), the
box (``robot_collision_box``; the stand too) or the worker (``robot_collision_worker``).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..errors import ConfigError
from ..ranges import check_ranges, ranged
from ..sim import pybullet as _pybullet
from .robot_collision import PENETRATION, deepest_self_penetration, self_collision_pairs, touches
from .robot_urdf import cached_robot_urdf, panda_path

ARMS = {"left": 1.0, "right": -1.0}  # arm -> side of the world y axis it stands on
ARM_JOINTS = tuple(f"panda_joint{i}" for i in range(1, 8))
FINGER_JOINTS = ("panda_finger_joint1", "panda_finger_joint2")
GRASP_LINK = "panda_grasptarget"  # between the finger pads, 0.105 m from the hand flange
BASE_LINK = "panda_link0"
LIFT_JOINT = "torso_lift"
DRIVE_JOINT = "base_drive"
IK_OFFSET = -100.0  # the IK twins stand this far below the floor [m]
REASONS = ("robot_ik", "robot_joint_limit", "robot_collision_self", "robot_collision_box",
           "robot_collision_worker")
APPROACH_YAWS_DEG = (0.0, 30.0, 60.0)
GRASPS = list(itertools.product(APPROACH_YAWS_DEG, (False, True)))
"""Every grasp (approach yaw [deg], fingers flipped), in the order they are tried."""
# A "ready" pose of the left arm (world +y) that the null space pulls toward when an IK starts
# afresh: shoulder leaning forward, elbow bent, wrist bent back up. Chosen by hand; from it
# every location of the paper-code boundary is reachable (docs/robot.md). The right arm
# mirrors it: joints about the links' z axes (1, 3, 5, 7) change sign.
REST_LEFT = (0.0, 0.3, 0.0, -1.9, 0.0, 2.2, 0.8)
MIRRORED = (-1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0)  # joint signs of the mirrored (right) arm
SHAPING_CALLS = 10  # first IK calls pull toward the rest pose; later ones only converge
FINGER_CLEARANCE = 0.003  # each finger pad this far off the bar [m]
DEFAULT_IK_CALLS = 40


class RobotSpecError(ConfigError):
    """A robot setting outside its valid range; the message is one line."""


@dataclass(frozen=True)
class RobotSpec:
    """Where the robot stands and how close its grippers must come (world frame, metres)."""

    distance: float = ranged(1.75, "arm bases in front of the worker's feet (worker z) with "
                             "the base driven fully back [m]", 0.8, 2.5)
    drive_range: float = ranged(0.9, "travel of the mobile base toward the worker [m]",
                                0.0, 1.5)
    carry_reach: float = ranged(0.55, "box centre in front of the arm bases while the base "
                                "can follow it [m]", 0.2, 0.8)
    arm_spacing: float = ranged(1.0, "distance between the two arm bases [m]", 0.5, 2.0)
    mount_height: float = ranged(0.6, "height of the arm bases (top of the stand) [m]",
                                0.2, 1.6)
    lift_range: float = ranged(1.0, "travel of the vertical lift under the arm bases [m]",
                              0.0, 1.5)
    position_tolerance: float = ranged(0.01, "largest gripper-to-handle distance [m]",
                                      0.0005, 0.05)
    angle_tolerance_deg: float = ranged(3.0, "largest gripper tilt from the level box [deg]",
                                       0.1, 30.0)
    ik_calls: int = ranged(DEFAULT_IK_CALLS, "IK calls per arm and approach", 1, 500)

    def __post_init__(self):
        check_ranges(self, RobotSpecError)


def grasp_orientation(arm: str, yaw_deg: float, flip: bool = False) -> np.ndarray:
    """World-frame quaternion (x, y, z, w) of an arm's grasp frame on its handle.

    The grasp frame's z (approach) points into the handle horizontally, from the outside
    (yaw 0) turning toward the worker (+yaw: coming from the robot's side); its y (the finger
    closing direction) is vertical, up or (``flip``) down.
    """
    side, yaw = ARMS[arm], math.radians(yaw_deg)
    z = np.array([-math.sin(yaw), -side * math.cos(yaw), 0.0])
    y = np.array([0.0, 0.0, -1.0 if flip else 1.0])
    return matrix_to_quaternion(np.column_stack([np.cross(y, z), y, z]))


def matrix_to_quaternion(r: np.ndarray) -> np.ndarray:
    """A rotation matrix (3, 3) as PyBullet's quaternion (x, y, z, w)."""
    trace = np.trace(r)
    if trace > 0:  # the branch with the largest divisor is the numerically safe one
        s = 2.0 * math.sqrt(1.0 + trace)
        q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
        q[i], q[j], q[k] = s / 4, (r[j, i] + r[i, j]) / s, (r[k, i] + r[i, k]) / s
    return np.array(q)


def angle_between(a, b) -> float:
    """Rotation angle between two quaternions [rad]."""
    return 2.0 * math.acos(min(1.0, abs(float(np.dot(a, b)))))


class ArmSolution(NamedTuple):
    """One arm's IK answer: joint angles (7,) [rad], grasp position error [m] and tilt [rad];
    ``beyond_limits``: the target was reached only with a joint beyond its limit."""

    q: np.ndarray
    error_m: float
    angle_rad: float
    beyond_limits: bool


class Reach(NamedTuple):
    """Can the robot hold the box where it is? ``reason`` is empty when it can.

    ``q`` maps each arm to its joint angles (7,) [rad] (the best attempt's, also when
    unreachable); ``error_m``/``angle_deg`` are the worse arm's gripper residuals.
    """

    reachable: bool
    reason: str
    error_m: float
    angle_deg: float
    approach_yaw_deg: float
    flip: bool
    q: dict[str, np.ndarray]


class DualArmRobot:
    """Two Panda arms and their stand in a PyBullet client, looked up by joint and link name.

    Args:
        client: a PyBullet client id.
        spec: placement and tolerances.
    """

    def __init__(self, client: int, spec: RobotSpec | None = None):
        p = self.p = _pybullet()
        self.client, self.spec = client, spec or RobotSpec()
        s = self.spec
        # The robot's frame faces the worker: its x is the world's -x.
        facing = p.getQuaternionFromEuler([0.0, 0.0, math.pi])
        self.body = p.loadURDF(str(cached_robot_urdf(s)), [s.distance, 0.0, 0.0], facing,
                               useFixedBase=True, physicsClientId=client)
        self.body_joints, self.body_links = self._names(self.body, "base")
        # PyBullet's IK runs on one plain Panda per arm, kept IK_OFFSET below the floor at its
        # arm's base pose: the same kinematics, out of every contact test and picture.
        self.arms, self.joints, self.links = {}, {}, {}
        for arm in ARMS:
            self.arms[arm] = p.loadURDF(str(panda_path()), [0, 0, IK_OFFSET], facing,
                                        useFixedBase=True, physicsClientId=client)
            self.joints[arm], self.links[arm] = self._names(self.arms[arm], BASE_LINK)
        self.set_base(0.0, 0.0)
        info = [p.getJointInfo(self.arms["left"], self.joints["left"][n], physicsClientId=client)
                for n in ARM_JOINTS]
        self.lower = np.array([i[8] for i in info])
        self.upper = np.array([i[9] for i in info])
        self.rest = {"left": np.array(REST_LEFT), "right": np.array(REST_LEFT) * MIRRORED}
        self._self_pairs = self_collision_pairs(p, self.body, client)
        # PyBullet's IK answers for the movable joints (arm and fingers) in index order.
        self._movable = [n for n, i in sorted(self.joints["left"].items(), key=lambda kv: kv[1])
                         if p.getJointInfo(self.arms["left"], i,
                                           physicsClientId=client)[2] != p.JOINT_FIXED]
        self.opening = 0.0
        for arm in ARMS:
            self.set_arm(arm, self.rest[arm])

    def _names(self, body: int, base: str) -> tuple[dict[str, int], dict[str, int]]:
        """Joint name -> index and link name -> index (the base link, named ``base``, = -1)."""
        p, joints, links = self.p, {}, {base: -1}
        for i in range(p.getNumJoints(body, physicsClientId=self.client)):
            info = p.getJointInfo(body, i, physicsClientId=self.client)
            joints[info[1].decode()] = i
            links[info[12].decode()] = i
        return joints, links

    def set_base(self, lift: float, drive: float) -> None:
        """Raise the crossbar (and both arms) ``lift`` [m] above its lowest position and drive
        the base ``drive`` [m] toward the worker from its home."""
        p, c = self.p, self.client
        self.lift = float(lift)
        p.resetJointState(self.body, self.body_joints[LIFT_JOINT], float(lift),
                          physicsClientId=c)
        p.resetJointState(self.body, self.body_joints[DRIVE_JOINT], float(drive),
                          physicsClientId=c)
        for arm, helper in self.arms.items():
            state = p.getLinkState(self.body, self.body_links[f"{arm}_{BASE_LINK}"],
                                   computeForwardKinematics=True, physicsClientId=c)
            frame = (np.array(state[4]) + np.array([0.0, 0.0, IK_OFFSET]), state[5])
            # A base is placed by its centre of mass, not by its link frame.
            inertial = p.getDynamicsInfo(helper, -1, physicsClientId=c)[3:5]
            at, turn = p.multiplyTransforms(*frame, *inertial)
            p.resetBasePositionAndOrientation(helper, at, turn, physicsClientId=c)

    def drive_for(self, box_x: float) -> float:
        """The drive that puts the arm bases ``carry_reach`` beyond a box centre at world
        ``box_x`` [m], within the drive's travel: the base keeps the box at arm's length."""
        s = self.spec
        return float(np.clip(s.distance - s.carry_reach - box_x, 0.0, s.drive_range))

    def shoulder(self, arm: str) -> np.ndarray:
        """The arm's shoulder (the axis of its second joint, the origin of ``panda_link1``),
        world frame [m]."""
        state = self.p.getLinkState(self.body, self.body_links[f"{arm}_panda_link1"],
                                    computeForwardKinematics=True, physicsClientId=self.client)
        return np.array(state[4])

    def joint_values(self) -> dict[str, float]:
        """Every movable joint of the robot's URDF by name: the lift, both arms, the fingers."""
        p, c = self.p, self.client
        return {name: p.getJointState(self.body, i, physicsClientId=c)[0]
                for name, i in self.body_joints.items()
                if p.getJointInfo(self.body, i, physicsClientId=c)[2] != p.JOINT_FIXED}

    def _set_twin(self, arm: str, q: np.ndarray) -> None:
        """Set the arm's IK twin alone (the robot is set once the IK has its answer)."""
        for name, angle in zip(ARM_JOINTS, q, strict=True):
            self.p.resetJointState(self.arms[arm], self.joints[arm][name], float(angle),
                                   physicsClientId=self.client)

    def _twin_residual(self, arm: str, position, orientation) -> tuple[float, float]:
        """Grasp position error [m] and tilt [rad] of the arm's IK twin, as if it stood at
        the arm's base."""
        state = self.p.getLinkState(self.arms[arm], self.links[arm][GRASP_LINK],
                                    computeForwardKinematics=True, physicsClientId=self.client)
        at = np.array(state[4]) - np.array([0.0, 0.0, IK_OFFSET])
        return float(np.linalg.norm(at - position)), angle_between(state[5], orientation)

    def set_arm(self, arm: str, q: np.ndarray) -> None:
        """Set an arm's seven joints [rad], in the robot and its IK twin (the fingers keep
        their opening)."""
        p, c = self.p, self.client
        for name, angle in zip(ARM_JOINTS, q, strict=True):
            p.resetJointState(self.arms[arm], self.joints[arm][name], float(angle),
                              physicsClientId=c)
            p.resetJointState(self.body, self.body_joints[f"{arm}_{name}"], float(angle),
                              physicsClientId=c)

    def open_fingers(self, bar_radius: float) -> None:
        """Open both grippers just wider than a bar of ``bar_radius`` [m]."""
        p, c = self.p, self.client
        self.opening = bar_radius + FINGER_CLEARANCE
        for arm, helper in self.arms.items():
            for name in FINGER_JOINTS:
                p.resetJointState(helper, self.joints[arm][name], self.opening,
                                  physicsClientId=c)
                p.resetJointState(self.body, self.body_joints[f"{arm}_{name}"], self.opening,
                                  physicsClientId=c)

    def grasp_pose(self, arm: str) -> tuple[np.ndarray, np.ndarray]:
        """The arm's grasp frame: world position [m] and quaternion (x, y, z, w)."""
        state = self.p.getLinkState(self.body, self.body_links[f"{arm}_{GRASP_LINK}"],
                                    computeForwardKinematics=True, physicsClientId=self.client)
        return np.array(state[4]), np.array(state[5])

    def solve_arm(self, arm: str, position: np.ndarray, orientation: np.ndarray,
                  seed: np.ndarray | None = None) -> ArmSolution:
        """Put an arm's grasp frame at a pose with PyBullet's IK, called repeatedly.

        Without a seed, the first :data:`SHAPING_CALLS` calls pull the null space toward the
        rest pose; later calls pass the current answer as the rest pose, so nothing pulls the
        gripper off its target while the iteration converges. With a seed (the previous pose
        on a path) the null space pulls toward the seed throughout: the arm tracks the path
        with the least joint motion. If the answer leaves a joint limit, the iteration
        continues from the answer clipped to the limits.

        Args:
            arm: ``left`` or ``right``.
            position: target grasp point, world frame (3,) [m].
            orientation: target quaternion (x, y, z, w).
            seed: starting joint angles (7,) [rad]; default the rest pose.
        """
        p, body, spec = self.p, self.arms[arm], self.spec
        shift = np.array([0.0, 0.0, IK_OFFSET])  # the IK twin stands that far down
        position = np.asarray(position, dtype=float)
        q = np.array(self.rest[arm] if seed is None else seed, dtype=float)
        self._set_twin(arm, q)
        order = [self._movable.index(n) for n in ARM_JOINTS]
        fingers = [self.opening] * (len(self._movable) - len(ARM_JOINTS))
        lower = [*self.lower, *([0.0] * len(fingers))]
        upper = [*self.upper, *([0.04] * len(fingers))]
        ranges = [hi - lo for lo, hi in zip(lower, upper, strict=True)]
        error = angle = math.inf
        beyond, history = False, []
        for call in range(spec.ik_calls):
            rest = (self.rest[arm] if seed is None else seed) if call < SHAPING_CALLS else q
            answer = p.calculateInverseKinematics(
                body, self.links[arm][GRASP_LINK], list(position + shift), list(orientation),
                lowerLimits=lower, upperLimits=upper, jointRanges=ranges,
                restPoses=[*rest, *fingers], maxNumIterations=50, residualThreshold=1e-6,
                physicsClientId=self.client)
            q = np.asarray(answer)[order]
            inside = bool(np.all((q >= self.lower - 1e-6) & (q <= self.upper + 1e-6)))
            if not inside:
                self._set_twin(arm, q)
                beyond |= self._within(*self._twin_residual(arm, position, orientation))
                q = np.clip(q, self.lower, self.upper)
            self._set_twin(arm, q)
            error, angle = self._twin_residual(arm, position, orientation)
            history.append(error + angle * 0.1)  # 0.1 m per rad: a tilt weighs like a miss
            if self._within(error, angle, 0.1):
                break
            # Stalled (out of reach, or pinned at a limit): more calls will not help. A seeded
            # solve starts next to its answer, so five calls without progress tell.
            if call >= (5 if seed is not None else SHAPING_CALLS + 5) and \
                    history[-6] - history[-1] < 1e-4:
                break
        self.set_arm(arm, q)
        return ArmSolution(q, error, angle, beyond and not self._within(error, angle))

    def holds_handle(self, arm: str, target: np.ndarray, grasp: tuple[float, bool]) -> bool:
        """Is the arm's grasp frame, as the joints are set, on ``target`` (world frame [m])
        with ``grasp``, within the tolerances?"""
        return self._within(*self._residual(arm, target, grasp_orientation(arm, *grasp)))

    def _within(self, error: float, angle: float, fraction: float = 1.0) -> bool:
        """Both residuals within ``fraction`` of their tolerances."""
        spec = self.spec
        return (error <= fraction * spec.position_tolerance
                and angle <= fraction * math.radians(spec.angle_tolerance_deg))

    def _residual(self, arm: str, position, orientation) -> tuple[float, float]:
        at, turn = self.grasp_pose(arm)
        return float(np.linalg.norm(at - position)), angle_between(turn, orientation)

    def collisions(self, box: int | None = None, worker: int | None = None) -> list[str]:
        """Reasons (of :data:`REASONS`) for the robot's current pose touching anything.

        Args:
            box: the box's body id, if it is in the world.
            worker: the worker's body id, if it is in the world.
        """
        p, c = self.p, self.client
        found = []
        if deepest_self_penetration(p, self.body, self._self_pairs, c) > PENETRATION:
            found.append("robot_collision_self")
        for name, other in (("robot_collision_box", box), ("robot_collision_worker", worker)):
            if other is not None and touches(p, self.body, other, c):
                found.append(name)
        return found

    def reach(self, targets: dict[str, np.ndarray], box: int | None = None,
              worker: int | None = None, grasps: list[tuple[float, bool]] | None = None,
              seed: dict[str, np.ndarray] | None = None) -> Reach:
        """Solve both arms for their grasp points and check the pose (see the module doc).

        Tries each grasp (approach yaw, fingers flipped) in turn and keeps the first pose that
        passes every check; otherwise reports the attempt that got furthest (IK failure <
        joint limit < collision) with its reasons.

        Args:
            targets: arm -> its grasp point, world frame (3,) [m].
            box: the box's body id (already placed), for collision checks.
            worker: the worker's body id (already posed), for collision checks.
            grasps: the grasps to try; default :data:`GRASPS` (all of them).
            seed: arm -> starting joint angles (7,) [rad], e.g. the previous pose on a path;
                default the rest pose.
        """
        best = None  # (stage, reasons, solutions, grasp)
        for grasp in grasps or GRASPS:
            solutions = {arm: self.solve_arm(arm, targets[arm], grasp_orientation(arm, *grasp),
                                             None if seed is None else seed[arm])
                         for arm in ARMS}
            failed = [s for s in solutions.values() if not self._within(s.error_m, s.angle_rad)]
            if failed:
                stage, reasons = (1, ["robot_joint_limit"]) if any(
                    s.beyond_limits for s in failed) else (0, ["robot_ik"])
            else:
                for arm, s in solutions.items():
                    self.set_arm(arm, s.q)
                reasons = self.collisions(box, worker)
                stage = 2 if reasons else 3
            if best is None or stage > best[0]:
                best = (stage, reasons, solutions, grasp)
            if stage == 3:
                break
        stage, reasons, solutions, grasp = best
        for arm, s in solutions.items():
            self.set_arm(arm, s.q)
        return Reach(stage == 3, ";".join(reasons),
                     max(s.error_m for s in solutions.values()),
                     math.degrees(max(s.angle_rad for s in solutions.values())), grasp[0],
                     grasp[1], {arm: s.q for arm, s in solutions.items()})
