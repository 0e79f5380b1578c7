"""Collision-free carries of the box, planned with OMPL.

The planning space is the box centre (worker frame, x y z [m]) and the robot's lift [m]: the
box stays level and square to the worker, so its pose is its position, and the lift decides
where the arms start. A pose is valid when both arms hold the box there with the carry's grasp
(PyBullet's IK within tolerance, inside joint limits) and nothing touches: the robot itself and
its stand, the box, the worker (at rest while the box travels), and the box the worker.

RRT-Connect grows trees of such states. Each tree state keeps the arms' configuration it was
reached with, and an edge is valid only when the arms, starting from that configuration,
follow the box along it: a pose every :data:`EDGE_RESOLUTION_M` (and halved where needed), the
IK seeded by the previous pose, no joint moving more than :data:`MAX_JOINT_STEP_RAD` between
poses, ending in the next state's configuration. So the IK never jumps to another branch
(elbow up or down, wrist flipped) mid-carry. OMPL's simplifier drops states where a direct
edge passes the same check, and the carry is the chain of poses checked along the final edges;
a trapezoidal speed profile gives each its time.

Planning is deterministic for a seed in a process that has not planned before: OMPL's random
generator can be seeded only once per process, so :func:`plan_carries` plans each carry in a
new process.
"""

from __future__ import annotations

import itertools
import math
import time
from typing import NamedTuple

import numpy as np

from ..errors import ConfigError
from .robot import GRASPS, Reach
from .robot_collision import clearance, touches

EDGE_RESOLUTION_M = 0.02  # poses checked along every edge, at most this far apart
# Largest joint motion between two poses [rad] (the lift's [m]): the arms' IK answers of
# neighbouring poses on one branch differ by far less, a switch to another branch (elbow up or
# down, wrist flipped) by far more.
MAX_JOINT_STEP_RAD = 0.1
# Longest edge RRT-Connect adds [m]: OMPL's default (a fifth of the space's diagonal, 0.7 m)
# costs 35 IK solutions per edge, and most long edges fail; short ones grow the trees faster.
EDGE_RANGE = 0.2
MAX_HALVINGS = 3  # spacing halved at most this often where a joint moves more (to 2.5 mm)
# Largest difference between the configuration the arms arrive in at a tree state and the one
# the state is known with; the arms move between the two holding the box still (checked).
MAX_RECONFIGURATION_RAD = 0.3
SPEED_M_S, ACCEL_M_S2 = 0.25, 0.5  # the box's cruise speed and acceleration
JOINT_SPEED_RAD_S = 0.5  # the arms' joints at the box's cruise speed, at most
DEFAULT_BUDGET = 5000  # about a minute here; the paper's starts need 600-1,200
LIFT_CANDIDATES = 11  # lift heights tried, lowest first, for the start and the handover
# Where the box may go, worker frame [m]: around the worker and the robot, above the floor.
BOUNDS = {"x": (-1.0, 1.0), "y": (0.15, 2.6), "z": (0.15, 1.9)}
# Why a carry cannot be planned, in the order they are found (a later one got further).
PLAN_REASONS = ("unreachable_handover", "unreachable_start", "no_path")
# Shoulder (joint 2) to grasp point of a stretched Panda: 0.316 + 0.0825 + 0.393 + 0.088 +
# 0.107 + 0.105 m along the links of its URDF, rounded up; farther is out of reach.
ARM_REACH_M = 1.1


class PlannerError(ConfigError):
    """A planner setting outside its range; the message is one line."""


class Waypoint(NamedTuple):
    """One pose of a planned carry: time [s], box centre (3,) worker frame [m], the lift [m]
    (the base's drive follows the box, :meth:`~.world.World.bring_robot`), and each arm's
    seven joint angles [rad]."""

    time: float
    location: np.ndarray
    lift: float
    q: dict[str, np.ndarray]


class Plan(NamedTuple):
    """A planned carry. ``reason`` is empty when the robot can carry the box; else one of
    :data:`PLAN_REASONS`, with what failed. Waypoints run from the start to the handover."""

    reason: str
    grasp: tuple[float, bool] | None
    waypoints: list[Waypoint]
    planning_s: float
    length_m: float
    clearance_m: float
    checks: int  # robot poses checked while planning (all grasps tried)

    @property
    def ok(self) -> bool:
        return self.reason == ""


def _ompl():
    from ompl import base as ob
    from ompl import geometric as og
    from ompl import util as ou

    ou.setLogLevel(ou.LOG_WARN)
    return ob, og, ou


_SEEDED: list[int] = []  # the seed OMPL was given in this process (it takes one only)


def _seed_ompl(ou, seed: int) -> None:
    """Seed OMPL's generator, once per process: later searches continue its stream, so a
    process's plans are reproducible as a sequence (:func:`.carries.plan_carries` gives each
    plan its own process)."""
    if not _SEEDED:
        ou.RNG.setSeed(seed + 1)  # OMPL treats a seed of 0 as "none"
        _SEEDED.append(seed)
    elif _SEEDED[0] != seed:
        raise PlannerError(f"seed = {seed} cannot be set: OMPL in this process was seeded "
                           f"with {_SEEDED[0]} (plan_carries gives each plan a new process)")


class CarryPlanner:
    """Plans carries in one :class:`~.world.World`.

    Args:
        world: the scene (worker, box, robot).
        seed: OMPL's random seed, set at this process's first search (see
            :func:`_seed_ompl`).
        budget: robot poses checked per grasp (IK and collisions); a plan not found within it
            is ``no_path``. A budget of work rather than of time keeps the plan a function of
            the seed on any machine.
    """

    def __init__(self, world, seed: int = 0, budget: int = DEFAULT_BUDGET):
        if not (isinstance(seed, int) and seed >= 0):
            raise PlannerError(f"seed = {seed!r} is not allowed (use an integer >= 0)")
        if isinstance(budget, bool) or not isinstance(budget, int) or not \
                100 <= budget <= 1_000_000:
            raise PlannerError(f"budget = {budget!r} is outside 100-1000000 poses")
        self.world, self.seed, self.budget = world, seed, budget
        self.checks = 0  # robot poses checked for the current plan
        self._cache: dict[tuple, object] = {}

    # -- states -------------------------------------------------------------------------
    def holds(self, location, lift: float, grasp, posture=None, seed=None):
        """The robot's hold of the box at ``location`` and ``lift`` with ``grasp``: a
        :class:`~.robot.Reach`, unreachable also when the box touches the worker (unless the
        worker takes ``posture``, its grip on the box). ``seed``: arm -> joint angles the IK
        starts from (a neighbouring pose); without one it starts from the ready pose, so the
        answer is a function of the state alone, and is cached as such."""
        location = np.asarray(location, dtype=float)
        key = (*np.round(location, 9), round(float(lift), 9), grasp, posture is not None)
        if seed is None and key in self._cache:
            return self._cache[key]
        self.checks += 1
        world = self.world
        if seed is None and not self._within_reach(location, lift):
            reach = Reach(False, "robot_ik", math.inf, math.inf, grasp[0], grasp[1], {})
        else:
            reach = world.reach(location, posture, [grasp], seed, lift=lift)
            if reach.reachable and posture is None and touches(
                    world.p, world.box.body_id, world.worker.body_id, world.client):
                reach = reach._replace(reachable=False, reason="box_touches_worker")
        if seed is None:
            self._cache[key] = reach
        return reach

    def _within_reach(self, location, lift: float) -> bool:
        """Can each grasp point be within :data:`ARM_REACH_M` of its arm's shoulder? A cheap
        test that spares the IK most of the states a sampler draws."""
        world = self.world
        world.bring_robot(location, lift)
        robot = world.robot
        return all(np.linalg.norm(target - robot.shoulder(arm)) <= ARM_REACH_M
                   for arm, target in world.grasp_targets().items())

    def _lifts(self, location, grasp, posture=None) -> tuple[list[float], object]:
        """The lifts (of :data:`LIFT_CANDIDATES`) at which the box can be held at
        ``location``, and the last hold tried (its reason, when there is none)."""
        lifts, last = [], None
        for lift in np.linspace(0.0, self.world.robot.spec.lift_range, LIFT_CANDIDATES):
            last = self.holds(location, float(lift), grasp, posture)
            if last.reachable:
                lifts.append(float(lift))
        return lifts, last

    # -- planning -----------------------------------------------------------------------
    def plan(self, start, location, posture=None) -> Plan:
        """Plan the carry from ``start`` to the handover at ``location`` (worker frame [m]),
        where the worker takes ``posture``. Tries each grasp in turn (the robot cannot change
        its grip mid-carry) and keeps the first that gives a path, else the furthest failure."""
        began, self.checks = time.perf_counter(), 0
        start, location = np.asarray(start, float), np.asarray(location, float)
        worst = None
        for grasp in GRASPS:
            plan = self._plan_grasp(start, location, posture, grasp, began)
            if plan.ok:
                return plan
            rank = PLAN_REASONS.index(plan.reason.split(":")[0])
            if worst is None or rank > worst[0]:
                worst = (rank, plan)
        self.world.pose_worker(None)
        return worst[1]

    def _plan_grasp(self, start, location, posture, grasp, began) -> Plan:
        def failed(reason: str) -> Plan:
            return Plan(reason, grasp, [], time.perf_counter() - began, math.nan, math.nan,
                        self.checks)

        self.world.pose_worker(posture)
        lifts1, reach1 = self._lifts(location, grasp, posture)
        self.world.pose_worker(None)
        if not lifts1:
            return failed(f"unreachable_handover: {reach1.reason}")
        lifts0, reach0 = self._lifts(start, grasp)
        if not lifts0:
            return failed(f"unreachable_start: {reach0.reason}")
        # Every lift that holds the box is a start (or goal) state: the search picks the one
        # from which the arms can move on.
        chain = self._search([np.array([*start, h]) for h in lifts0],
                             [np.array([*location, h]) for h in lifts1], grasp, posture)
        if chain is None:
            return failed("no_path")
        timed = _time_parametrise([Waypoint(0.0, point[:3].copy(), float(point[3]), q)
                                   for point, q in chain])
        length = float(sum(np.linalg.norm(b.location - a.location)
                           for a, b in itertools.pairwise(timed)))
        return Plan("", grasp, timed, time.perf_counter() - began, length,
                    self._clearance(timed, posture), self.checks)

    def _search(self, starts, goals, grasp, posture) -> list[tuple] | None:
        """OMPL's RRT-Connect from any of ``starts`` to any of ``goals`` (x, y, z, lift; the
        goals share one location, where the worker takes ``posture``): the simplified path's
        poses, (state (4,), arm -> joint angles), or None when no path was found within the
        budget."""
        ob, og, ou = _ompl()
        _seed_ompl(ou, self.seed)  # before OMPL makes any generator
        space = ob.RealVectorStateSpace(4)
        bounds = ob.RealVectorBounds(4)
        for k, (lo, hi) in enumerate(BOUNDS.values()):
            bounds.setLow(k, lo)
            bounds.setHigh(k, hi)
        bounds.setLow(3, 0.0)
        bounds.setHigh(3, self.world.robot.spec.lift_range)
        space.setBounds(bounds)
        si = ob.SpaceInformation(space)
        location = goals[0][:3]

        def key(v) -> tuple:
            return tuple(round(float(v[k]), 9) for k in range(4))

        def seeded(point, seed):
            """The hold at a 4-vector state with the IK seeded by ``seed`` (None: rest)."""
            at_goal = bool(np.allclose(point[:3], location, atol=1e-9))
            if at_goal:
                self.world.pose_worker(posture)
            reach = self.holds(point[:3], point[3], grasp, posture if at_goal else None, seed)
            if at_goal:
                self.world.pose_worker(None)
            return reach

        # Each tree state keeps the arms' configuration it was first reached with. An edge is
        # valid when the arms, starting from its source's configuration, follow the box along
        # it (IK seeded by the previous pose, EDGE_RESOLUTION_M apart, halved where a joint
        # moves more than MAX_JOINT_STEP_RAD) and reach its end's configuration; the poses
        # along every valid edge are kept, so the path is made of checked poses only.
        # A state's configuration is set when an edge first leaves it (the IK from the rest
        # pose) or first arrives at it (the poses followed along that edge).
        configs: dict[tuple, dict] = {}
        edges: dict[tuple, list] = {}

        def advance(point, q, target, depth) -> list | None:
            """Poses from (point, q) to target, each joint step within the limit."""
            reach = seeded(target, q)
            if not reach.reachable:
                return None
            if max(_largest_step(q, reach.q), abs(target[3] - point[3])) <= MAX_JOINT_STEP_RAD:
                return [(target, reach.q)]
            if depth >= MAX_HALVINGS:
                return None
            middle = (point + target) / 2.0
            first = advance(point, q, middle, depth + 1)
            if first is None:
                return None
            rest = advance(middle, first[-1][1], target, depth + 1)
            return None if rest is None else first + rest

        def follow(a, b) -> bool:
            a = np.array([a[0], a[1], a[2], a[3]])
            b = np.array([b[0], b[1], b[2], b[3]])
            if key(a) not in configs:  # a new state of the goal's tree
                first = seeded(a, None)
                if not first.reachable:
                    return False
                configs[key(a)] = first.q
            chain = [(a, configs[key(a)])]
            n = max(1, math.ceil(np.linalg.norm(b - a) / EDGE_RESOLUTION_M))
            for f in np.linspace(0.0, 1.0, n + 1)[1:]:
                step = advance(*chain[-1], a + f * (b - a), 0)
                if step is None:
                    return False
                chain += step
            known = configs.get(key(b))
            if known is not None:  # arrive in the configuration b is known with
                moves = self._reconfigure(b, chain[-1][1], known, grasp)
                if moves is None:
                    return False
                chain += moves
            elif not np.allclose(b[:3], location, atol=1e-9):  # the goal's stays open
                configs[key(b)] = chain[-1][1]
            edges[key(a), key(b)] = chain
            return True

        def valid(state) -> bool:  # only the cheap reach test: the edges check the rest
            return bool(self._within_reach(np.array([state[0], state[1], state[2]]), state[3]))

        class Following(ob.MotionValidator):
            def checkMotion(self, a, b, *last) -> bool:
                return bool(follow(a, b))

        si.setStateValidityChecker(valid)
        si.setMotionValidator(Following(si))
        si.setup()

        def state(vector):
            allocated = si.allocState()
            for k in range(4):
                allocated[k] = float(vector[k])
            return allocated

        problem = ob.ProblemDefinition(si)
        for vector in starts:
            problem.addStartState(state(vector))
        goal = ob.GoalStates(si)
        for vector in goals:
            goal.addState(state(vector))
        problem.setGoal(goal)
        planner = og.RRTConnect(si)
        planner.setRange(EDGE_RANGE)
        planner.setProblemDefinition(problem)
        planner.setup()
        spent = self.checks
        solved = planner.solve(ob.PlannerTerminationCondition(
            lambda: bool(self.checks - spent >= self.budget)))
        if not (solved and problem.hasExactSolution()):
            return None
        path = problem.getSolutionPath()
        og.PathSimplifier(si).reduceVertices(path)  # between tree states only
        keys = [key(path.getState(i)) for i in range(path.getStateCount())]
        chain = edges[keys[0], keys[1]]
        for edge in itertools.pairwise(keys[1:]):
            chain = chain + edges[edge][1:]
        return chain

    def _reconfigure(self, point, q0, q1, grasp) -> list | None:
        """The arms moving from ``q0`` to ``q1`` with the box held still at ``point`` (4,):
        straight in joint space, in steps of at most :data:`MAX_JOINT_STEP_RAD`, every pose
        holding the handles within the robot's tolerances and touching nothing. None when the
        configurations are more than :data:`MAX_RECONFIGURATION_RAD` apart or a pose fails."""
        largest = _largest_step(q0, q1)
        if largest > MAX_RECONFIGURATION_RAD:
            return None
        world, robot = self.world, self.world.robot
        world.bring_robot(point[:3], point[3])
        targets = world.grasp_targets()
        poses = []
        for f in np.linspace(0.0, 1.0, math.ceil(largest / MAX_JOINT_STEP_RAD) + 1)[1:]:
            q = {arm: q0[arm] + f * (q1[arm] - q0[arm]) for arm in q0}
            for arm, angles in q.items():
                robot.set_arm(arm, angles)
            if not all(robot.holds_handle(arm, targets[arm], grasp) for arm in q) or \
                    robot.collisions(world.box.body_id, world.worker.body_id):
                return None
            poses.append((point, q))
        return poses

    def _clearance(self, waypoints, posture) -> float:
        """The smallest distance between the robot and the worker along the carry [m] (the
        worker at rest, and in ``posture`` at the handover)."""
        world, smallest = self.world, math.inf
        for i, w in enumerate(waypoints):
            last = i == len(waypoints) - 1
            world.pose_worker(posture if last else None)
            world.bring_robot(w.location, w.lift)
            for arm, q in w.q.items():
                world.robot.set_arm(arm, q)
            smallest = min(smallest, clearance(world.p, world.robot.body,
                                               world.worker.body_id, world.client))
        world.pose_worker(None)
        return float(smallest)


def _largest_step(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> float:
    """The largest joint motion between two configurations of the arms [rad]."""
    return max(float(np.abs(a[arm] - b[arm]).max()) for arm in a)


def _time_parametrise(waypoints: list[Waypoint]) -> list[Waypoint]:
    """Times along a trapezoidal speed profile over the path's length (box and lift); where
    the arms move more than that length allows at :data:`JOINT_SPEED_RAD_S` (they reconfigure
    with the box held still), the step counts as long as that motion needs."""
    per_rad = SPEED_M_S / JOINT_SPEED_RAD_S
    steps = [max(math.hypot(float(np.linalg.norm(b.location - a.location)), b.lift - a.lift),
                 _largest_step(a.q, b.q) * per_rad)
             for a, b in itertools.pairwise(waypoints)]
    s = np.concatenate([[0.0], np.cumsum(steps)])
    total = s[-1]
    ramp = min(SPEED_M_S**2 / ACCEL_M_S2 / 2.0, total / 2.0)  # distance to reach cruise speed
    peak = math.sqrt(2.0 * ACCEL_M_S2 * ramp)
    t_ramp = peak / ACCEL_M_S2 if peak > 0 else 0.0
    cruise = (total - 2.0 * ramp) / peak if peak > 0 else 0.0

    def at(x: float) -> float:
        if x <= ramp:
            return math.sqrt(2.0 * x / ACCEL_M_S2)
        if x <= total - ramp:
            return t_ramp + (x - ramp) / peak
        return 2.0 * t_ramp + cruise - math.sqrt(max(0.0, 2.0 * (total - x) / ACCEL_M_S2))

    return [w._replace(time=at(float(x))) for w, x in zip(waypoints, s, strict=False)]
