"""The posture solver compiled with numba: the same Levenberg-Marquardt, one location at a time.

Why: the numpy solver (``PostureSolver(backend="numpy")``) is batched over N locations, and
with only 25 joints and 15 task rows per location its time went into temporaries, copies and
small batched LAPACK calls rather than arithmetic. Here each location runs the whole iteration
in a few scratch arrays: the tasks of :mod:`.kernel_tasks`, the damped step through Woodbury's
identity with a Cholesky factor of the SPD m x m system (instead of an LU solve), the step
scaling, the projection onto the joint limits and the accept/reject rule of
``PostureSolver.iterate_numpy``, with the same settings. A rejected trial posture's Jacobian
is never computed, and the m x m product J D⁻¹Jᵀ is one small BLAS call (numba's ``np.dot``,
through SciPy's BLAS), faster than scalar loops (experiments/bench_evaluate.py times the
solve), with results that differ from them only by rounding.

Per-location arithmetic (no fastmath, one BLAS thread) makes every result bit-identical
whatever else is in the batch. A location stops early only when a step is
rejected at the largest damping: every later iteration would repeat that same rejected step,
so stopping changes nothing. (Stopping once steps become small is not used: on the paper-code
grid most locations still take or reject sizeable steps up to the last iteration.)

Compiled on first use and cached on disk (``cache=True``); ``posture_solver`` runs it (solving
the lattice nodes a sweep needs) before any worker process forks, so workers never compile.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .anthropometry import GRAVITY
from .kernel_tasks import (
    JIT,
    ROWS,
    effort_relations,
    jacobian,
    residuals,
    row_touches,
    row_weights,
)
from .skeleton import PALM_NORMAL
from .tasks import EFFORT_JOINTS

TAKES = 12
"""Where the task's scalars hold each hand's share of the object (left, right): a hand that
takes none has no grip to miss."""

LAM_MIN, LAM_MAX = 1e-6, 1e6  # the damping's range, as in PostureSolver.iterate_numpy


@njit(**JIT)
def _step(q, jt, res, lam, fresh, kin, task, work):
    """The damped, scaled step of ``PostureSolver`` at q into ``work[6]`` (nq,).

    Solves (D + JᵀJ) x = grad through Woodbury, (D + JᵀJ)⁻¹ = D⁻¹ - D⁻¹Jᵀ(I + J D⁻¹Jᵀ)⁻¹J D⁻¹,
    J the weighted Jacobian, with a Cholesky factor of the SPD m x m matrix. Column j of J is
    zero outside rows ``span[j, 0]:span[j, 1]`` (the rows its joint can move): the scalar loops
    run over that range, and ``work``'s J buffers are zero elsewhere, so the dense product is
    exact. Zero rows (a hinge that holds) give identity rows, which decouple exactly.
    """
    limits, span = kin[3], kin[6]
    scalars, root = task[2], task[3]
    wjt, wres, scaled, inner, rhs, u, step, grad, hold = work
    nq = q.shape[0]
    for a in range(ROWS):
        rhs[a] = 0.0
    if fresh:  # J, the residuals and q are new: weight J, take the gradient and the held set
        for a in range(ROWS):
            wres[a] = res[a] * root[a]
        for j in range(nq):
            g = 0.0
            for a in range(span[j, 0], span[j, 1]):
                w = jt[j, a] * root[a]
                wjt[j, a] = w
                g += w * wres[a]
            g += limits[3, j] * (q[j] - limits[2, j])
            grad[j] = g
            # A joint held at a limit by a gradient pushing outward sits out the step.
            held = (q[j] <= limits[0, j] and g > 0.0) or (q[j] >= limits[1, j] and g < 0.0)
            hold[j] = 1e9 if held else 0.0
    for j in range(nq):
        lo, hi = span[j, 0], span[j, 1]
        g = grad[j]
        d = 1.0 / (limits[3, j] + lam + hold[j])
        uj = d * g
        u[j] = uj
        for a in range(lo, hi):
            scaled[j, a] = wjt[j, a] * d
            rhs[a] += wjt[j, a] * uj
    np.dot(scaled.T, wjt, inner)
    # Cholesky of I + inner, left-looking in the lower triangle; the diagonal keeps 1 / L_aa.
    for a in range(ROWS):
        for b in range(a):
            s = inner[a, b]
            for k in range(b):
                s -= inner[a, k] * inner[b, k]
            inner[a, b] = s * inner[b, b]
        s = inner[a, a] + 1.0
        for k in range(a):
            s -= inner[a, k] * inner[a, k]
        inner[a, a] = 1.0 / math.sqrt(s)
    for a in range(ROWS):
        s = rhs[a]
        for k in range(a):
            s -= inner[a, k] * rhs[k]
        rhs[a] = s * inner[a, a]
    for a in range(ROWS - 1, -1, -1):
        s = rhs[a]
        for k in range(a + 1, ROWS):
            s -= inner[k, a] * rhs[k]
        rhs[a] = s * inner[a, a]
    biggest = 0.0
    for j in range(nq):
        s = 0.0
        for a in range(span[j, 0], span[j, 1]):
            s += scaled[j, a] * rhs[a]
        step[j] = -(u[j] - s)
        biggest = max(biggest, abs(step[j]))
    # Scale, not clip, so that the step keeps its direction.
    scale = min(1.0, scalars[6] / max(biggest, 1e-12))
    for j in range(nq):
        step[j] *= scale


@njit(**JIT)
def _solve_one(start, target, iterations, kin, task, scratch, work, bufs):
    """Levenberg-Marquardt from ``start`` (nq,); the posture ends in ``bufs[0]``.

    Returns the number of iterations run (fewer than ``iterations`` only when a step is
    rejected at the largest damping, since every later iteration would repeat that step), the
    cost at the final posture, and whether ``scratch`` still holds that posture's kinematics
    (no trial step was rejected after it was reached).
    """
    limits, scalars = kin[3], task[2]
    q, q_new, jt, res, res_new = bufs
    nq = q.shape[0]
    step = work[6]
    for j in range(nq):
        q[j] = start[j]
    cost = residuals(q, target, kin, task, scratch, res)
    if iterations > 0:  # no step, no Jacobian: a start scored as it is costs one evaluation
        jacobian(kin, task, scratch, res, jt)
    lam = scalars[5]
    used, fresh, current = iterations, True, True
    for it in range(iterations):
        _step(q, jt, res, lam, fresh, kin, task, work)
        for j in range(nq):
            q_new[j] = min(max(q[j] + step[j], limits[0, j]), limits[1, j])
        cost_new = residuals(q_new, target, kin, task, scratch, res_new)
        if cost_new <= cost:
            q, q_new = q_new, q
            res, res_new = res_new, res
            cost = cost_new
            jacobian(kin, task, scratch, res, jt)  # the scratch holds q's kinematics
            lam = min(max(lam * 0.3, LAM_MIN), LAM_MAX)
            fresh, current = True, True
        elif lam >= LAM_MAX:
            used, current = it + 1, False
            break
        else:  # same q, J and gradient: only the damping changes for the next trial
            lam = min(max(lam * 10.0, LAM_MIN), LAM_MAX)
            fresh, current = False, False
    for j in range(nq):
        bufs[0][j] = q[j]
    return used, cost, current


@njit(**JIT)
def solve_batch(starts, targets, iterations, kin, task, q_out, pos_out, rot_out, axes_out,
                error_out, com_out, used_out, cost_out):
    """Solve N locations one by one; outputs in ``KinematicState``'s posture-last layout.

    Args:
        starts: (N, nq) starting postures [rad].
        targets: (N, 3, 3) left handle, right handle and box centre, world frame [m].
        iterations: the iteration budget per location.
        kin, task: the tuples of :class:`PackedSolver`.
        q_out: (N, nq) solved postures [rad].
        pos_out, rot_out, axes_out: (L, 3, N), (L, 3, 3, N), (nq, 3, N) their kinematics.
        error_out: (N,) the worse taking hand's distance from its grip point [m].
        com_out: (N, 3) centre of mass with the box [m].
        used_out: (N,) iterations run.
        cost_out: (N,) the solver's objective at the solved posture.
    """
    n, nq = starts.shape
    n_links, n_mass = kin[2].shape[0], kin[4].shape[0]
    scratch = (np.empty((n_links, 3)), np.empty((n_links, 3, 3)), np.empty((nq, 3)),
               np.empty((nq, 3)), np.empty((n_mass, 3)), np.empty((4, 3)),
               np.empty((task[5].shape[0] + 1, 4)), np.empty((n_links, 4)))
    work = (np.zeros((nq, ROWS)), np.empty(ROWS), np.zeros((nq, ROWS)),
            np.empty((ROWS, ROWS)), np.empty(ROWS), np.empty(nq), np.empty(nq), np.empty(nq),
            np.empty(nq))
    bufs = (np.empty(nq), np.empty(nq), np.empty((nq, ROWS)), np.empty(ROWS), np.empty(ROWS))
    pos, rot, axes, vec = scratch[0], scratch[1], scratch[2], scratch[5]
    links = task[0]
    for i in range(n):
        used, cost, current = _solve_one(starts[i], targets[i], iterations, kin, task,
                                         scratch, work, bufs)
        used_out[i], q = used, bufs[0]
        if not current:  # the scratch holds a rejected trial's kinematics: q's again
            cost = residuals(q, targets[i], kin, task, scratch, bufs[3])
        cost_out[i] = cost
        worst = 0.0
        for side in range(2):
            if task[2][TAKES + side] == 0.0:  # a hand that takes nothing misses nothing
                continue
            d = 0.0
            for c in range(3):
                e = pos[links[2 * side], c] - targets[i, side, c]
                d += e * e
            worst = max(worst, math.sqrt(d))
        error_out[i] = worst
        for j in range(nq):
            q_out[i, j] = q[j]
            for c in range(3):
                axes_out[j, c, i] = axes[j, c]
        for c in range(3):
            com_out[i, c] = vec[3, c]
            for k in range(n_links):
                pos_out[k, c, i] = pos[k, c]
                for d in range(3):
                    rot_out[k, c, d, i] = rot[k, c, d]


class PackedSolver:
    """A ``PostureSolver``'s model, weights and limits as the arrays the kernel reads.

    Args:
        solver: the solver whose model and settings are packed (its backend is irrelevant).

    Attributes:
        kin: steps (S, 4) int, geometry (S, 4), ancestors (L, nq) bool, limits (4, nq) =
            lower, upper, neutral, preference [rad, 1], mass links (P,), masses (P, 4) =
            offset [m] and mass [kg], span (nq, 2) = the task rows each joint can move,
            joint children (nq,) = the link each joint turns.
        task: links (5,) = left grip, left hand, right grip, right hand, gaze; vectors (5, 3)
            = palm normals, medial directions, line of sight; scalars (12,) = eye cone [rad],
            safe rectangle x0, x1, y0, y1 [m], damping, largest step [rad], total mass [kg],
            free share of strength [1], the hamstrings' line (hip flexion at a straight knee
            [rad], slope [1]) and strain per radian beyond it [1/rad]; root weights (ROWS,)
            and weights (ROWS,); the effort joints (E,: knee, hip, lumbar, the order the
            hamstrings' term relies on), g / their strength (E,) [1/(kg m)], their relations
            (E, nq), the masses each does not carry (E, K; -1 pads) and the mass it does carry
            (E,) [kg].
    """

    def __init__(self, solver) -> None:
        model, s = solver.model, solver.weights
        steps = model.steps
        self.nq, self.n_links = model.nq, len(model.link_names)
        origin = np.zeros((len(steps), 3))
        for k, st in enumerate(steps):
            for i, v in st.origin:
                origin[k, i] = v
        kin_steps = np.array([(st.parent, st.child, st.col, st.axis) for st in steps], np.int64)
        geometry = np.column_stack([origin, [st.sign for st in steps]])  # (S, 4)
        limits = np.stack([model.lower, model.upper, solver.neutral, solver.preference])
        loads = solver.grip_loads()
        grips = [model.link_index("left_grip"), model.link_index("right_grip")]
        mass_link = np.array([i for i, _ in model.mass_points] + grips, np.int64)  # (P,)
        mass_geom = np.zeros((len(mass_link), 4))  # offset in the link [m], mass [kg]
        for p, (i, com) in enumerate(model.mass_points):
            for c, v in com:
                mass_geom[p, c] = v
            mass_geom[p, 3] = model.link_mass[i]
        mass_geom[-2:, 3] = loads["left_grip"], loads["right_grip"]
        links = np.array([model.link_index(n) for n in
                          ("left_grip", "left_hand", "right_grip", "right_hand", "gaze")],
                         np.int64)
        effort_joints = np.array([model.index(j) for j in EFFORT_JOINTS], np.int64)
        relations = effort_relations(model.ancestors, model.joint_children, effort_joints)
        touches = row_touches(model.ancestors, links, mass_link, relations).T  # (nq, ROWS)
        span = np.zeros((self.nq, 2), np.int64)
        for j in range(self.nq):
            rows = np.flatnonzero(touches[j])
            span[j] = (rows[0], rows[-1] + 1) if len(rows) else (0, 0)
        self.kin = (kin_steps, geometry, model.ancestors.copy(), limits, mass_link, mass_geom,
                    span, model.joint_children.astype(np.int64))
        vectors = np.array([PALM_NORMAL["left"], PALM_NORMAL["right"], (0.0, -1.0, 0.0),
                            (0.0, 1.0, 0.0), solver.sight], dtype=float)
        x0, x1, y0, y1 = solver.support
        m = s.balance_margin
        takes = solver.task.grip_shares()
        scalars = np.array([solver.eye_cone, x0 + m, x1 - m, y0 + m, y1 - m, s.damping,
                            np.radians(s.max_step_deg), mass_geom[:, 3].sum(), s.effort_free,
                            *solver.hamstring, *takes])
        weights = row_weights(s, takes)
        scale = np.array([GRAVITY / solver.strengths[j] for j in EFFORT_JOINTS])
        carries = model.ancestors[mass_link][:, effort_joints].T  # (E, P)
        outside = np.full((len(effort_joints), max(1, (~carries).sum(axis=1).max())), -1,
                          np.int64)
        for k, row in enumerate(~carries):
            outside[k, :row.sum()] = np.flatnonzero(row)
        carried = carries.astype(float) @ mass_geom[:, 3]
        self.task = (links, vectors, scalars, np.sqrt(weights), weights, effort_joints, scale,
                     relations, outside, carried)

    def run(self, targets: np.ndarray, start: np.ndarray, iterations: int):
        """Solve (N, 3, 3) targets from (N, nq) starts.

        Returns:
            q (N, nq), pos (L, 3, N), rot (L, 3, 3, N), axes (nq, 3, N), hand error (N,),
            centre of mass (N, 3), iterations run (N,) and the objective at q (N,).
        """
        n = targets.shape[0]
        out = (np.empty((n, self.nq)), np.empty((self.n_links, 3, n)),
               np.empty((self.n_links, 3, 3, n)), np.empty((self.nq, 3, n)), np.empty(n),
               np.empty((n, 3)), np.empty(n, np.int64), np.empty(n))
        solve_batch(np.ascontiguousarray(start, dtype=float),
                    np.ascontiguousarray(targets, dtype=float), int(iterations), self.kin,
                    self.task, *out)
        return out
