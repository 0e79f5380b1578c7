"""Whole-body bimanual posture solver: batched damped Gauss-Newton over N box locations.

For each box location the worker grips both handles and takes the posture that minimises a
weighted sum of squares:

- **hands** (weight ``hand``): each grip point on its handle (with the task's ``hands`` one of
  "right" or "left", that hand's grip point on the object's centre, and no task for the other);
- **palms** (``palm``): each taking palm's normal pointing at the box (medially);
- **gaze** (``gaze``): the box centre within 25° (eye rotation) of the head's natural line of
  sight, which is 15° below the head's horizontal (Grandjean); beyond that cone the head turns
  (only when the task's ``gaze`` is "on", the default);
- **balance** (``balance``): the centre of mass, the box's weight in the hands included, kept
  ``balance_margin`` inside the feet's support rectangle (a hinge: no cost inside it);
- **effort** (``effort``): the load gravity puts on the knee, hip and lower-back extensors beyond
  ``effort_free`` of each one's strength, and the hamstrings' stretch beyond their passive
  length (a hip flexed past what the knee's flexion allows); this is what bends the knees to a
  low box (:func:`.tasks.effort`);
- **joint preference** (``JOINT_PREFERENCE``): each joint pulled toward its neutral angle with
  its own weight; these make the motion humanlike (see the table's comments).

Low boxes have more than one local minimum (a stoop, a semi-squat, a squat): the warm-start
lattice is solved from each whole-body strategy of ``STRATEGY_DEG`` and keeps, node by node,
the posture of lowest cost.

Levenberg-Marquardt with a damping per location: a step that raises the cost is rejected and
the damping raised, so the stiff hand task and the soft preferences cannot make the iteration
oscillate. Joint limits hold by projection; a joint held at a limit sits out the step. Each
location starts from :mod:`~ergohandover.warm_start`'s interpolated lattice and runs a fixed
number of iterations with per-location arithmetic, so its posture never depends on the rest of
the batch (deterministic and order-independent).

Two backends compute the same iteration: ``numba`` (default, :mod:`.kernel`: one location at a
time, compiled; a converged location stops early) and ``numpy`` (batched over locations, here;
the reference the kernel is tested against). They agree to rounding on converged locations.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from ..errors import ConfigError
from ..frames import worker_to_world
from ..ranges import check_ranges, ranged
from .anthropometry import BodySpec
from .kinematics import KinematicModel, KinematicState
from .skeleton import build_skeleton
from .task import TaskSpec
from .tasks import Targets, stack_tasks
from .warm_start import StartLattice

# Joint -> (neutral angle [deg], preference weight). Higher weight: the twin moves that joint
# less. What each changes: ankle/knee - how readily the twin squats rather than stoops;
# hip/lumbar flexion - the split of a stoop between hip hinge and spine; side bend/twist - how
# reluctantly the trunk and neck leave the sagittal plane; clavicle - shrugging; shoulder vs
# elbow - reaching with the upper arm or unfolding the forearm; wrist/pronation - how much
# the hand, rather than the arm, adapts to the handle.
JOINT_PREFERENCE: dict[str, tuple[float, float]] = {
    "ankle_flexion": (0.0, 4.0),
    "knee_flexion": (0.0, 1.5),
    "hip_flexion": (0.0, 1.5),
    "lumbar_flexion": (0.0, 2.5),
    "lumbar_side_bend": (0.0, 3.0),
    "lumbar_twist": (0.0, 3.0),
    "neck_flexion": (0.0, 0.4),
    "neck_side_bend": (0.0, 3.0),
    "neck_twist": (0.0, 1.5),
    "clavicle_elevation": (0.0, 3.0),
    "shoulder_flexion": (0.0, 0.10),
    "shoulder_abduction": (0.0, 0.4),
    "shoulder_rotation": (0.0, 0.3),
    "elbow_flexion": (60.0, 0.05),
    "forearm_pronation": (0.0, 0.15),
    "wrist_flexion": (0.0, 0.6),
    "wrist_deviation": (0.0, 0.8),
}
# Where the lattice's solves start: standing, upper arms slightly forward, forearms forward.
START_POSTURE_DEG = {"shoulder_flexion": 20.0, "elbow_flexion": 80.0}
# Whole-body strategies for a low box, as joint angles [deg] added to the standing start. People
# lifting freely use neither a pure stoop (knees straight) nor a pure squat (knees fully bent)
# but something between (Burgess-Limerick & Abernethy 1997, Hum Factors 39:141; Davis,
# Splittstoesser & Marras 2003, Occup Ergon 3:99); the cost has a local minimum near each, so
# every lattice node is solved from each strategy and keeps the one of lowest cost.
STRATEGY_TIE = 1e-3  # cost difference below which two strategies' postures count as one [1]
STRATEGY_DEG: dict[str, dict[str, float]] = {
    "stoop": {},
    "semi-squat": {"ankle_flexion": 15.0, "knee_flexion": 50.0, "hip_flexion": 50.0,
                   "lumbar_flexion": 30.0},
    "squat": {"ankle_flexion": 20.0, "knee_flexion": 100.0, "hip_flexion": 90.0,
              "lumbar_flexion": 20.0},
}
BACKENDS = ("numba", "numpy")
SIGHT_PITCH_DEG = 15.0  # natural line of sight below the head's horizontal (Grandjean)
EYE_CONE_DEG = 25.0  # eye rotation from the natural line of sight held without strain


def support_rectangle(body: BodySpec) -> tuple[float, float, float, float]:
    """The feet's support rectangle (x0, x1, y0, y1), heel to toe and outer edge to outer
    edge, world frame [m]."""
    seg = body.segments()
    half = seg.hip_width / 2 + seg.foot_width / 2
    return (-seg.heel_to_ankle, seg.foot_length - seg.heel_to_ankle, -half, half)


def handover_targets(task: TaskSpec, locations: np.ndarray) -> Targets:
    """Handles and box centre in the world frame for (N, 3) worker-frame box locations."""
    left, right = task.handles(locations)
    return Targets(worker_to_world(left), worker_to_world(right), worker_to_world(locations))


class SolverSettingsError(ConfigError):
    """A solver setting outside its valid range; the message is one line."""


@dataclass(frozen=True)
class SolverSettings:
    """Weights and iteration budget of the posture solver (model parameters, documented above).

    Attributes:
        hand: weight of the grip-on-handle task [1/m²].
        palm: weight of palm orientation [1].
        gaze: weight of the line of sight beyond the eyes' cone [1/rad²].
        balance: weight of the centre-of-mass hinge [1/m²].
        balance_margin: how far inside the support rectangle the hinge starts [m].
        effort: weight of the load on the knees, hips and lower back beyond ``effort_free`` of
            their strength [1] (the task that makes the twin bend its knees to a low box).
        effort_free: the share of each joint's strength held at no cost [1]: 0.14, the
            endurance limit of intermittent static contractions held for an hour (Björkstén &
            Jonsson 1977, Scand J Work Environ Health 3:23-27; 7.9% for sustained ones).
        hamstring_stiffness: the effort task's strain per radian of hip flexion beyond the
            hamstrings' passive line (:meth:`BodySpec.hamstring_line`) [1/rad].
        damping: initial Levenberg-Marquardt damping [1].
        max_step_deg: largest change of any joint in one iteration [deg].
        iterations: iterations from the interpolated start. 10: on 20,000 random paper-code
            locations, 98.0% score exactly as with 12 (flags, paper score, REBA, RULA) and
            97.1% as with 60 (98.4% with 12), for two iterations (a tenth of the time) less
            (``experiments/tools/iteration_budget.py``, the twin sized by the body model).
        lattice_iterations: iterations for the lattice postures, from each strategy.
        preference_scale: factor on every joint-preference weight (``JOINT_PREFERENCE``).
        joint_preference_scales: (joint, factor) pairs on single joints' preference weights,
            joints named as in ``JOINT_PREFERENCE`` (both sides for an arm joint).
        range_of_motion: fraction of each joint's range the solver may use; both limits move
            toward 0 (the neutral stance) by this factor.
        strategies: the whole-body strategies (``STRATEGY_DEG``) each lattice node is solved
            from; the node keeps the posture of lowest cost.
        warm_start: how a location is solved. "lattice" (the default): ``iterations`` from the
            coarse lattice's interpolation. "fine": the interpolation of a fine lattice (every
            ``fine_spacing``) whose nodes are solved as "lattice" solves a location, scored
            as it is; where the check of ``FineLattice.unsure`` fails (the location's cell
            scores unalike and is not smooth within ``fine_check_deg``) the location is solved
            as "lattice" solves it. Its flags and scores equal "lattice"'s at >= 99.5 % of the
            paper's 3 mm grid, in about half the time (``experiments/bench_sweep.py
            --compare``). It is the evaluation's (``twin/evaluate.py``), which scores.
        fine_spacing: the fine lattice's node spacing [m].
        fine_check_deg: how far a smooth cell's parallel edges may disagree [deg].

    The four before the warm-start fields exist for the sensitivity study; at their defaults
    they change nothing.
    """

    hand: float = 1e4
    palm: float = 2.0
    gaze: float = 1.0
    balance: float = 1e4
    balance_margin: float = 0.02
    effort: float = 10.0
    effort_free: float = 0.14
    hamstring_stiffness: float = 20.0
    damping: float = 1e-3
    max_step_deg: float = 15.0
    iterations: int = 10
    lattice_iterations: int = 100
    preference_scale: float = ranged(1.0, "factor on every joint-preference weight", 0.1, 10.0)
    joint_preference_scales: tuple[tuple[str, float], ...] = ()
    range_of_motion: float = ranged(1.0, "fraction of each joint's range of motion used",
                                    0.5, 1.0)
    strategies: tuple[str, ...] = tuple(STRATEGY_DEG)
    warm_start: str = ranged("lattice", "how a location is solved: from the coarse lattice, "
                             "or a checked fine lattice of solved postures",
                             choices=("lattice", "fine"))
    fine_spacing: float = ranged(0.006, "the fine lattice's node spacing [m]", 0.002, 0.05)
    fine_check_deg: float = ranged(0.2, "how far a smooth cell's parallel edges may disagree "
                                   "[deg]", 0.0, 10.0)

    def __post_init__(self):
        check_ranges(self, SolverSettingsError)
        unknown = [n for n in self.strategies if n not in STRATEGY_DEG]
        if unknown or not self.strategies or len(set(self.strategies)) < len(self.strategies):
            raise SolverSettingsError(
                f"strategies = {self.strategies!r} is not allowed (use one or more of "
                f"{', '.join(STRATEGY_DEG)}, each once)")
        for pair in self.joint_preference_scales:
            name, factor = pair
            if name not in JOINT_PREFERENCE:
                raise SolverSettingsError(
                    f"joint_preference_scales: {name!r} is not a joint (use "
                    f"{', '.join(JOINT_PREFERENCE)})")
            if not 0.1 <= factor <= 10.0:
                raise SolverSettingsError(f"joint_preference_scales: {name} factor {factor!r} "
                                          "is outside the valid range 0.1-10")

    def preference_factors(self, joints: list[str]) -> np.ndarray:
        """(nq,) the factors on the preference weights of ``joints`` (base names)."""
        single = dict(self.joint_preference_scales)
        return np.array([self.preference_scale * single.get(j, 1.0) for j in joints])


class Solution(NamedTuple):
    """Solved postures of N box locations."""

    q: np.ndarray  # (N, nq) [rad]
    hand_error: np.ndarray  # (N,) the worse taking hand's distance from its grip point [m]
    com: np.ndarray  # (N, 3) centre of mass with the box, world frame [m]
    state: KinematicState  # forward kinematics of q
    cost: np.ndarray | None = None  # (N,) the solver's objective at q (None: not an optimiser's)


class PostureSolver:
    """Whole-body handover postures of one worker for one task.

    Args:
        body: the worker.
        task: the box and its handles.
        settings: solver weights and budget.
        backend: ``numba`` (compiled, per location) or ``numpy`` (batched reference).
    """

    def __init__(self, body: BodySpec | None = None, task: TaskSpec | None = None,
                 settings: SolverSettings | None = None, backend: str = "numba"):
        if backend not in BACKENDS:
            raise ConfigError(f"backend = {backend!r} is not allowed (use 'numba' or 'numpy')")
        self.backend = backend
        self.body = body or BodySpec()
        self.task = task or TaskSpec()
        self.settings = settings or SolverSettings()
        # The task decides whether the gaze row counts: with gaze "off" its weight is zero.
        self.weights = (self.settings if self.task.gaze == "on"
                        else replace(self.settings, gaze=0.0))
        self.model = KinematicModel(build_skeleton(self.body))
        # The solver's own model: a reduced range of motion narrows only what it may use.
        self.model.lower = self.model.lower * self.settings.range_of_motion
        self.model.upper = self.model.upper * self.settings.range_of_motion
        self.support = support_rectangle(self.body)
        self.strengths = self.body.joint_strengths_nm()
        self.hamstring = (*self.body.hamstring_line(), self.settings.hamstring_stiffness)
        base = [n.removeprefix("left_").removeprefix("right_") for n in self.model.joint_names]
        self.neutral = np.radians([JOINT_PREFERENCE[b][0] for b in base])  # (nq,)
        self.preference = (np.array([JOINT_PREFERENCE[b][1] for b in base])
                           * self.settings.preference_factors(base))  # (nq,)
        standing = np.radians([START_POSTURE_DEG.get(b, 0.0) for b in base])
        self.standing = np.clip(standing, self.model.lower, self.model.upper)
        pitch = np.radians(SIGHT_PITCH_DEG)
        self.sight = np.array([np.cos(pitch), 0.0, -np.sin(pitch)])  # gaze-link frame
        self.eye_cone = np.radians(EYE_CONE_DEG)
        self._lattice: StartLattice | None = None
        self._packed = None  # the kernel's arrays, built on first use

    @property
    def lattice(self) -> StartLattice:
        """The warm-start lattice (about thirteen hundred nodes, scaled to the stature); each
        node is solved, once from each strategy of ``settings.strategies``, the first time a
        location needs it (:meth:`StartLattice.prepare` solves a grid's nodes at once)."""
        if self._lattice is None:
            axes, _ = StartLattice.nodes(self.body.stature_m)
            self._lattice = StartLattice(axes, self.lattice_postures, self.model.nq)
        return self._lattice

    def lattice_postures(self, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(K, nq) converged postures at (K, 3) lattice nodes and (K,) the strategy each came
        from: every node solved from each strategy, the lowest cost kept."""
        best_q, best_cost = None, None
        choice = np.zeros(len(nodes), dtype=np.intp)
        for k, name in enumerate(self.settings.strategies):
            start = np.broadcast_to(self.strategy_start(name), (len(nodes), self.model.nq))
            q = self.iterate(nodes, start, self.settings.lattice_iterations).q
            cost = self.cost(nodes, q)
            if best_q is None:
                best_q, best_cost = q, cost
                continue
            # Two strategies that end in the same basin differ in cost by rounding and
            # unfinished convergence only; the earlier one keeps the node unless the later
            # is clearly lower, so the recorded strategy means a different posture.
            lower = cost < best_cost - STRATEGY_TIE
            best_q[lower], best_cost[lower], choice[lower] = q[lower], cost[lower], k
        return best_q, np.array(self.settings.strategies, dtype=object)[choice]

    def strategy_start(self, name: str) -> np.ndarray:
        """(nq,) the standing start with strategy ``name``'s leg and trunk angles, in limits."""
        q = self.standing.copy()
        for joint, deg in STRATEGY_DEG[name].items():
            q[self.model.index(joint)] = np.radians(deg)
        return np.clip(q, self.model.lower, self.model.upper)

    def cost(self, locations: np.ndarray, q: np.ndarray) -> np.ndarray:
        """(N,) the solver's objective at postures q (N, nq) for box ``locations`` (N, 3)."""
        _, res, weight = stack_tasks(
            self.model.forward(q), self.targets(locations), self.weights, self.sight,
            self.eye_cone, self.support, self.weights.balance_margin, self.grip_loads(),
            self.strengths, self.hamstring, self.task.grip_shares())
        return self._cost(q, res, weight)

    def grip_loads(self) -> dict[str, float]:
        """The object's mass carried at each grip [kg] (the task's shares)."""
        left, right = self.task.grip_shares()
        return {"left_grip": self.task.box_mass_kg * left,
                "right_grip": self.task.box_mass_kg * right}

    def solve(self, locations: np.ndarray) -> Solution:
        """Postures for box centres at ``locations`` (N, 3), worker frame [m]."""
        locations = np.asarray(locations, dtype=float).reshape(-1, 3)
        return self.iterate(locations, self.lattice.start(locations), self.settings.iterations)

    def targets(self, locations: np.ndarray) -> Targets:
        """Handles and box centre in the world frame for (N, 3) worker-frame locations."""
        return handover_targets(self.task, locations)

    def iterate(self, locations: np.ndarray, start: np.ndarray, iterations: int) -> Solution:
        """Run ``iterations`` Levenberg-Marquardt steps from ``start`` (N, nq) [rad]."""
        if self.backend == "numpy":
            return self.iterate_numpy(locations, start, iterations)
        if self._packed is None:
            from .kernel import PackedSolver  # numba loads (and compiles) on first use only

            self._packed = PackedSolver(self)
        targets = self.targets(locations)
        q, pos, rot, axes, error, com, _, cost = self._packed.run(
            np.stack(targets, axis=1), start, iterations)
        return Solution(q, error, com, KinematicState(self.model, q, pos, rot, axes), cost)

    def iterate_numpy(self, locations: np.ndarray, start: np.ndarray,
                      iterations: int) -> Solution:
        """:meth:`iterate` batched in numpy: the reference implementation."""
        s = self.weights
        targets = self.targets(locations)
        extra = self.grip_loads()
        takes = self.task.grip_shares()
        max_step = np.radians(s.max_step_deg)
        lower, upper = self.model.lower, self.model.upper

        def tasks(q):
            return stack_tasks(self.model.forward(q), targets, s, self.sight, self.eye_cone,
                               self.support, s.balance_margin, extra, self.strengths,
                               self.hamstring, takes)

        q = np.array(start, dtype=float)
        jac, res, weight = tasks(q)
        root_weight = np.sqrt(weight)  # (m,)
        cost = self._cost(q, res, weight)
        lam = np.full(len(q), s.damping)
        for _ in range(iterations):
            wjac = jac * root_weight[None, :, None]  # (N, m, nq)
            grad = (np.einsum("nmq,nm->nq", wjac, res * root_weight)
                    + self.preference * (q - self.neutral))
            # Joints held at a limit by a gradient pushing outward take no part in the step.
            held = ((q <= lower) & (grad > 0)) | ((q >= upper) & (grad < 0))
            inv_diag = 1.0 / (self.preference + lam[:, None] + 1e9 * held)  # (N, nq)
            step = -_woodbury_solve(wjac, inv_diag, grad)
            # Scale, not clip, so that the step keeps its direction.
            biggest = np.abs(step).max(axis=1, keepdims=True)
            step *= np.minimum(1.0, max_step / np.maximum(biggest, 1e-12))
            q_new = np.clip(q + step, lower, upper)
            jac_new, res_new, _ = tasks(q_new)
            cost_new = self._cost(q_new, res_new, weight)
            better = cost_new <= cost
            q = np.where(better[:, None], q_new, q)
            jac = np.where(better[:, None, None], jac_new, jac)
            res = np.where(better[:, None], res_new, res)
            cost = np.where(better, cost_new, cost)
            lam = np.clip(np.where(better, lam * 0.3, lam * 10.0), 1e-6, 1e6)
        state = self.model.forward(q)
        error = np.max([np.linalg.norm(state.point(f"{side}_grip") - target, axis=1)
                        for side, target, share in zip(("left", "right"), targets[:2], takes,
                                                       strict=True) if share > 0], axis=0)
        return Solution(q, error, state.com(extra), state, cost)

    def _cost(self, q: np.ndarray, res: np.ndarray, weight: np.ndarray) -> np.ndarray:
        """(N,) total cost: weighted task residuals plus joint preferences."""
        return 0.5 * ((res**2) @ weight + ((q - self.neutral) ** 2) @ self.preference)


def _woodbury_solve(wjac: np.ndarray, inv_diag: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve (D + Jᵀ J) x = rhs for diagonal D through the m x m system (m < nq rows).

    Woodbury: (D + JᵀJ)⁻¹ = D⁻¹ - D⁻¹Jᵀ (I + J D⁻¹ Jᵀ)⁻¹ J D⁻¹.

    Args:
        wjac: (N, m, nq) weighted Jacobian J.
        inv_diag: (N, nq) the inverse of D's diagonal.
        rhs: (N, nq).
    """
    scaled = wjac * inv_diag[:, None, :]  # J D⁻¹, (N, m, nq)
    inner = np.matmul(scaled, wjac.transpose(0, 2, 1))  # (N, m, m)
    m = inner.shape[1]
    inner[:, np.arange(m), np.arange(m)] += 1.0
    u = inv_diag * rhs  # D⁻¹ rhs
    v = np.linalg.solve(inner, np.einsum("nmq,nq->nm", wjac, u)[..., None])[..., 0]
    return u - np.einsum("nmq,nm->nq", scaled, v)
