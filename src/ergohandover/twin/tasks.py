"""The posture solver's tasks: residuals and Jacobians of what a worker handing over a box does.

Each task is a residual r(q) that is zero when the task is met, and its Jacobian dr/dq, for N
postures at once. Hinge tasks (gaze, balance) are zero, with a zero Jacobian, while they hold.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .anthropometry import GRAVITY
from .kinematics import KinematicState
from .skeleton import PALM_NORMAL

EFFORT_JOINTS = ("knee_flexion", "hip_flexion", "lumbar_flexion")
"""The joints whose extensors hold a load in front of the body, in the effort task's order
(the kernel finds the hamstrings' knee and hip as the first two)."""


class Targets(NamedTuple):
    """What the worker reaches for, world frame [m]: (N, 3) each."""

    left: np.ndarray  # left handle grip point
    right: np.ndarray  # right handle grip point
    box: np.ndarray  # box centre (what the eyes look at)


class Stack(NamedTuple):
    """Stacked tasks of N postures."""

    jac: np.ndarray  # (N, m, nq)
    res: np.ndarray  # (N, m)
    weight: np.ndarray  # (m,)


def cross_columns(vectors: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """``vectors[:, :, j] x fixed`` for every column j: (N, 3, nq) x (N, 3) -> (N, 3, nq)."""
    vx, vy, vz = vectors[:, 0], vectors[:, 1], vectors[:, 2]  # (N, nq)
    fx, fy, fz = fixed[:, 0, None], fixed[:, 1, None], fixed[:, 2, None]
    return np.stack((vy * fz - vz * fy, vz * fx - vx * fz, vx * fy - vy * fx), axis=1)


def stack_tasks(st: KinematicState, targets: Targets, weights, sight: np.ndarray,
                eye_cone: float, support: tuple[float, float, float, float], margin: float,
                extra: dict[str, float], strengths: dict[str, float],
                hamstring: tuple[float, float, float],
                takes: tuple[float, float] = (0.5, 0.5)) -> Stack:
    """Every task of the handover posture.

    Args:
        st: forward kinematics of the N postures.
        targets: handles and box centre.
        weights: an object with ``hand``, ``palm``, ``gaze``, ``balance`` and ``effort``
            weights and the effort task's ``effort_free`` share of strength.
        sight: (3,) natural line of sight in the ``gaze`` link frame.
        eye_cone: eye rotation held without strain [rad].
        support: (x0, x1, y0, y1) feet's support rectangle, world frame [m].
        margin: how far inside the rectangle the balance hinge starts [m].
        extra: point masses carried at links (the object, shared by the taking hands) [kg].
        strengths: extensor strength of each of :data:`EFFORT_JOINTS` [N m].
        hamstring: the hamstrings' passive line, hip flexion at a straight knee [rad] and its
            slope per radian of knee flexion [1], and the strain per radian beyond it [1/rad].
        takes: each hand's (left, right) share of the object; a hand without one keeps its
            rows at zero weight (the kernel's row layout is the same for every task).
    """
    jacs, residuals, row_weights = [], [], []

    def add(jac: np.ndarray, res: np.ndarray, weight: float) -> None:
        jacs.append(jac)
        residuals.append(res)
        row_weights.append(np.full(res.shape[1], weight))

    for side, target, share in (("left", targets.left, takes[0]),
                                ("right", targets.right, takes[1])):
        grip, on = f"{side}_grip", float(share > 0)
        add(st.point_jacobian(grip), st.point(grip) - target, weights.hand * on)
        # Palm normal n onto the medial direction d: residual n - d (zero only when they
        # agree), Jacobian w_j x n.
        hand = f"{side}_hand"
        normal = st.rotation(hand) @ np.array(PALM_NORMAL[side])  # (N, 3)
        medial = np.array([0.0, -1.0 if side == "left" else 1.0, 0.0])
        add(cross_columns(st.angular_jacobian(hand), normal), normal - medial,
            weights.palm * on)
    # Gaze: only the angle between the line of sight and the box beyond the eyes' cone costs.
    look = targets.box - st.position("gaze")
    look /= np.linalg.norm(look, axis=1, keepdims=True)
    line = st.rotation("gaze") @ sight  # (N, 3)
    angle = np.arccos(np.clip(np.einsum("nc,nc->n", line, look), -1.0, 1.0))
    beyond = np.maximum(angle - eye_cone, 0.0)
    # d(angle)/dq_j = -look . (w_j x line) / sin(angle) = -w_j . (line x look) / sin(angle).
    turn = np.cross(line, look) / np.maximum(np.sin(angle), 1e-6)[:, None]  # (N, 3)
    d_angle = -np.einsum("nc,ncq->nq", turn, st.angular_jacobian("gaze"))
    add((d_angle * (beyond > 0)[:, None])[:, None, :], beyond[:, None], weights.gaze)
    # Balance: only the part of the centre of mass outside the safe rectangle costs.
    x0, x1, y0, y1 = support
    com = st.com(extra)[:, :2]
    outside = com - np.clip(com, [x0 + margin, y0 + margin], [x1 - margin, y1 - margin])
    add(st.com_jacobian(extra)[:, :2] * (outside != 0)[..., None], outside, weights.balance)
    add(*effort(st, extra, strengths, weights.effort_free, hamstring), weights.effort)
    return Stack(np.concatenate(jacs, axis=1), np.concatenate(residuals, axis=1),
                 np.concatenate(row_weights))


def effort(st: KinematicState, extra: dict[str, float], strengths: dict[str, float],
           free: float, hamstring: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """The strain of knees, hips and lower back: the load they hold beyond a free share of
    their strength, and the hamstrings' stretch beyond their passive length.

    For each joint J of :data:`EFFORT_JOINTS`, gravity's moment about its axis from everything
    it carries (the body above it and the box) is g c_z, with c = a_J × S_J (a_J the axis, S_J
    the subtree's mass-weighted lever arm). Its share of the joint's strength beyond ``free``,
    e_J, is a hinge: zero while the joint holds less. The task is one row, sqrt(Σ e_J²), whose
    square is the cost Σ e_J². A joint below J turns c as a whole (column a_i × c); a joint at
    or above J turns its own subtree (column a_J × (a_i × S_i)).

    The hamstrings span hip and knee: hip flexion beyond ``hip0 + slope · knee flexion`` (the
    passive line, :meth:`BodySpec.hamstring_line`) adds e_H = ``stiffness`` × the excess to the
    sum. Without it a load on the floor is taken by hanging the trunk past horizontal with
    straight knees, since gravity's moment about the back shrinks as the trunk hangs.

    Returns:
        Jacobian (N, 1, nq) [1/rad] and residual (N, 1) [1].
    """
    model = st.model
    axes, levers = st.joint_axes, st.subtree_levers(extra)  # (nq, 3, N) each
    n, columns = st.q.shape[0], np.arange(model.nq)
    squares, jac = np.zeros(n), np.zeros((model.nq, n))
    for name in EFFORT_JOINTS:
        joint = model.index(name)
        scale = GRAVITY / strengths[name]
        c = np.cross(axes[joint], levers[joint], axis=0)  # (3, N)
        share = c[2] * scale
        e = np.sign(share) * np.maximum(np.abs(share) - free, 0.0)
        below = model.ancestors[model.joint_children[joint]] & (columns != joint)
        above = model.ancestors[model.joint_children, joint]  # the joint itself included
        d = np.zeros((model.nq, n))
        a = axes[below]
        d[below] = a[:, 0] * c[1] - a[:, 1] * c[0]
        turned = np.cross(axes[above], levers[above], axis=1)  # (k, 3, N)
        d[above] = axes[joint][0] * turned[:, 1] - axes[joint][1] * turned[:, 0]
        squares += e * e
        jac += e * d * scale
    hip0, slope, stiffness = hamstring
    hip, knee = model.index("hip_flexion"), model.index("knee_flexion")
    stretch = stiffness * np.maximum(st.q[:, hip] - hip0 - slope * st.q[:, knee], 0.0)
    squares += stretch * stretch
    jac[hip] += stretch * stiffness
    jac[knee] -= stretch * stiffness * slope
    total = np.sqrt(squares)
    jac = np.divide(jac, total, out=np.zeros_like(jac), where=total > 0)
    return jac.T[:, None, :], total[:, None]
