"""The posture solver's tasks: residuals and Jacobians of what a worker handing over a box does.

Each task is a residual r(q) that is zero when the task is met, and its Jacobian dr/dq, for N
postures at once. Hinge tasks (gaze, balance) are zero, with a zero Jacobian, while they hold.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .kinematics import KinematicState
from .skeleton import PALM_NORMAL


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
                extra: dict[str, float]) -> Stack:
    """Every task of the handover posture.

    Args:
        st: forward kinematics of the N postures.
        targets: handles and box centre.
        weights: an object with ``hand``, ``palm``, ``gaze``, ``balance`` weights.
        sight: (3,) natural line of sight in the ``gaze`` link frame.
        eye_cone: eye rotation held without strain [rad].
        support: (x0, x1, y0, y1) feet's support rectangle, world frame [m].
        margin: how far inside the rectangle the balance hinge starts [m].
        extra: point masses carried at links (the box, half in each hand) [kg].
    """
    jacs, residuals, row_weights = [], [], []

    def add(jac: np.ndarray, res: np.ndarray, weight: float) -> None:
        jacs.append(jac)
        residuals.append(res)
        row_weights.append(np.full(res.shape[1], weight))

    for side, target in (("left", targets.left), ("right", targets.right)):
        grip = f"{side}_grip"
        add(st.point_jacobian(grip), st.point(grip) - target, weights.hand)
        # Palm normal n onto the medial direction d: residual n - d (zero only when they
        # agree), Jacobian w_j x n.
        hand = f"{side}_hand"
        normal = st.rotation(hand) @ np.array(PALM_NORMAL[side])  # (N, 3)
        medial = np.array([0.0, -1.0 if side == "left" else 1.0, 0.0])
        add(cross_columns(st.angular_jacobian(hand), normal), normal - medial, weights.palm)
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
    return Stack(np.concatenate(jacs, axis=1), np.concatenate(residuals, axis=1),
                 np.concatenate(row_weights))
