"""Kinematics and tasks of one posture, compiled: what :mod:`.kinematics` and :mod:`.tasks`
compute for N postures at once, written per posture for the numba solver of :mod:`.kernel`.

Why per posture: the solver's kernel runs one location at a time in a few scratch arrays, so
these loops carry no temporaries. The mathematics is that of the numpy modules (same frames,
lever arms, hinge tasks); only the order of the task rows differs, chosen so that the rows a
joint can move form one contiguous range (see :func:`row_touches`):

    rows 0-2 left grip, 3-5 left palm normal, 6-7 balance (x, y), 8 effort, 9 gaze,
    rows 10-12 right grip, 13-15 right palm normal.

Residuals and the Jacobian are separate calls: a trial step that is rejected never needs its
Jacobian, and ``_jacobian`` reuses the scratch ``_residuals`` left (frames, palm normals, the
gaze's turn vector, the masses' positions).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

ROWS = 16
GRIP_ROW, PALM_ROW = (0, 10), (3, 13)  # first row of each side's task
BALANCE_ROW, EFFORT_ROW, GAZE_ROW = 6, 8, 9
JIT = {"cache": True, "nogil": True, "error_model": "numpy"}


def row_weights(settings, takes: tuple[float, float] = (0.5, 0.5)) -> np.ndarray:
    """(ROWS,) task weights in the kernel's row order; a hand whose share of the object
    (``takes``: left, right) is zero has zero weights."""
    left, right = (float(share > 0) for share in takes)
    return np.array([*[settings.hand * left] * 3, *[settings.palm * left] * 3,
                     settings.balance, settings.balance, settings.effort, settings.gaze,
                     *[settings.hand * right] * 3, *[settings.palm * right] * 3])


def effort_relations(ancestors: np.ndarray, children: np.ndarray,
                     joints: np.ndarray) -> np.ndarray:
    """(E, nq) int64: 1 where joint i lies below effort joint J (it turns J's whole load), 2
    where it lies at or above J (it turns part of the load J carries), 0 otherwise."""
    below = ancestors[children[joints]].copy()  # (E, nq)
    below[np.arange(len(joints)), joints] = False
    above = ancestors[children][:, joints].T  # (E, nq), J itself included
    return np.where(below, 1, np.where(above, 2, 0)).astype(np.int64)


def row_touches(ancestors: np.ndarray, links: np.ndarray, mass_links: np.ndarray,
                relations: np.ndarray) -> np.ndarray:
    """(ROWS, nq) bool: can joint j move task row r? From ``model.ancestors`` (L, nq).

    ``links``: left grip, left hand, right grip, right hand, gaze; ``mass_links`` (P,);
    ``relations``: :func:`effort_relations`.
    """
    left_grip, left_hand, right_grip, right_hand, gaze = (ancestors[k] for k in links)
    com = ancestors[mass_links].any(axis=0)
    effort = (relations != 0).any(axis=0)
    return np.array([left_grip] * 3 + [left_hand] * 3 + [com] * 2 + [effort, gaze]
                    + [right_grip] * 3 + [right_hand] * 3)


@njit(**JIT)
def forward(q, steps, geometry, pos, rot, axes, jpos):
    """Link frames of one posture q (nq,) into pos (L, 3), rot (L, 3, 3), axes/jpos (nq, 3).

    ``steps`` (S, 4) int: parent, child, q column (-1 fixed), axis index; ``geometry`` (S, 4):
    origin in the parent frame [m] and the axis sign. As ``KinematicModel.forward``: frames
    are world-aligned at q = 0, so a joint about ±e_i turns only columns j, k of R. ``axes``
    are the joints' world axes, ``jpos`` their positions.
    """
    for c in range(3):
        pos[0, c] = 0.0
        for d in range(3):
            rot[0, c, d] = 1.0 if c == d else 0.0
    for s in range(steps.shape[0]):
        parent, child, col, i = steps[s, 0], steps[s, 1], steps[s, 2], steps[s, 3]
        ox, oy, oz = geometry[s, 0], geometry[s, 1], geometry[s, 2]
        for c in range(3):
            pos[child, c] = (pos[parent, c] + rot[parent, c, 0] * ox + rot[parent, c, 1] * oy
                             + rot[parent, c, 2] * oz)
        if col < 0:
            for c in range(3):
                for d in range(3):
                    rot[child, c, d] = rot[parent, c, d]
            continue
        sign = geometry[s, 3]
        cs, sn = math.cos(q[col]), math.sin(q[col]) * sign
        j, k = (i + 1) % 3, (i + 2) % 3
        for c in range(3):
            ri, rj, rk = rot[parent, c, i], rot[parent, c, j], rot[parent, c, k]
            rot[child, c, i] = ri
            rot[child, c, j] = rj * cs + rk * sn
            rot[child, c, k] = rk * cs - rj * sn
            axes[col, c] = ri * sign
            jpos[col, c] = pos[child, c]


@njit(**JIT)
def com(pos, rot, mass_link, mass_geom, where, out):
    """Centre of mass ``out`` (3,) of the point masses (links' and the box's).

    ``mass_link`` (P,), ``mass_geom`` (P, 4): offset in the link frame [m] and mass [kg]; the
    masses' world positions go to ``where`` (P, 3).
    """
    total = 0.0
    for c in range(3):
        out[c] = 0.0
    for p in range(mass_link.shape[0]):
        link, m = mass_link[p], mass_geom[p, 3]
        ox, oy, oz = mass_geom[p, 0], mass_geom[p, 1], mass_geom[p, 2]
        for c in range(3):
            w = pos[link, c] + rot[link, c, 0] * ox + rot[link, c, 1] * oy + rot[link, c, 2] * oz
            where[p, c] = w
            out[c] += m * w
        total += m
    for c in range(3):
        out[c] /= total


@njit(**JIT)
def residuals(q, target, kin, task, scratch, res):
    """Task residuals ``res`` (ROWS,) of posture q (nq,); returns its cost.

    ``target`` (3, 3): left handle, right handle, box centre, world frame [m]. ``kin`` and
    ``task`` are :class:`~.kernel.PackedSolver`'s tuples; ``scratch`` = pos, rot, axes, jpos,
    where, vec, of which vec (4, 3) keeps the palm normals, the gaze's turn vector and the
    centre of mass for :func:`jacobian`.
    """
    steps, geometry, limits, mass_link, mass_geom = kin[0], kin[1], kin[3], kin[4], kin[5]
    links, vectors, scalars, weight = task[0], task[1], task[2], task[4]
    effort_joints, effort_scale = task[5], task[6]
    pos, rot, axes, jpos, where, vec, eff = scratch[:7]
    forward(q, steps, geometry, pos, rot, axes, jpos)
    for side in range(2):
        grip, hand = links[2 * side], links[2 * side + 1]
        for c in range(3):
            res[GRIP_ROW[side] + c] = pos[grip, c] - target[side, c]
        # Palm normal n = R_hand @ palm onto the medial direction: residual n - medial.
        for c in range(3):
            n = (rot[hand, c, 0] * vectors[side, 0] + rot[hand, c, 1] * vectors[side, 1]
                 + rot[hand, c, 2] * vectors[side, 2])
            vec[side, c] = n
            res[PALM_ROW[side] + c] = n - vectors[2 + side, c]
    # Gaze: the angle between the line of sight and the box beyond the eyes' cone.
    gaze = links[4]
    lx, ly, lz = (target[2, 0] - pos[gaze, 0], target[2, 1] - pos[gaze, 1],
                  target[2, 2] - pos[gaze, 2])
    norm = math.sqrt(lx * lx + ly * ly + lz * lz)
    lx, ly, lz = lx / norm, ly / norm, lz / norm
    sx = rot[gaze, 0, 0] * vectors[4, 0] + rot[gaze, 0, 1] * vectors[4, 1] \
        + rot[gaze, 0, 2] * vectors[4, 2]
    sy = rot[gaze, 1, 0] * vectors[4, 0] + rot[gaze, 1, 1] * vectors[4, 1] \
        + rot[gaze, 1, 2] * vectors[4, 2]
    sz = rot[gaze, 2, 0] * vectors[4, 0] + rot[gaze, 2, 1] * vectors[4, 1] \
        + rot[gaze, 2, 2] * vectors[4, 2]
    angle = math.acos(min(max(sx * lx + sy * ly + sz * lz, -1.0), 1.0))
    beyond = max(angle - scalars[0], 0.0)
    res[GAZE_ROW] = beyond
    if beyond > 0.0:
        # d(angle)/dq_j = -w_j . turn, turn = (line x look) / sin(angle).
        sin = max(math.sin(angle), 1e-6)
        vec[2, 0] = (sy * lz - sz * ly) / sin
        vec[2, 1] = (sz * lx - sx * lz) / sin
        vec[2, 2] = (sx * ly - sy * lx) / sin
    # Balance: the centre of mass (box included) outside the safe rectangle.
    centre = vec[3]
    com(pos, rot, mass_link, mass_geom, where, centre)
    for c in range(2):
        res[BALANCE_ROW + c] = centre[c] - min(max(centre[c], scalars[1 + 2 * c]),
                                               scalars[2 + 2 * c])
    # Effort: each joint's load beyond the free share of its strength, as in tasks.effort;
    # eff[k] keeps c = a_J x S_J and e_J * g / strength for the Jacobian.
    # S_J = (all masses' moment - those J does not carry) - M_J p_J: the few masses below J
    # (feet, shanks, ...) are listed in ``outside``, so no loop runs over every mass.
    outside, carried = task[8], task[9]
    squares = 0.0
    for k in range(effort_joints.shape[0]):
        joint = effort_joints[k]
        sx, sy, sz = centre[0] * scalars[7], centre[1] * scalars[7], centre[2] * scalars[7]
        for i in range(outside.shape[1]):
            p = outside[k, i]
            if p < 0:
                break
            m = mass_geom[p, 3]
            sx -= m * where[p, 0]
            sy -= m * where[p, 1]
            sz -= m * where[p, 2]
        sx -= carried[k] * jpos[joint, 0]
        sy -= carried[k] * jpos[joint, 1]
        sz -= carried[k] * jpos[joint, 2]
        ax, ay, az = axes[joint, 0], axes[joint, 1], axes[joint, 2]
        cx, cy, cz = ay * sz - az * sy, az * sx - ax * sz, ax * sy - ay * sx
        share = cz * effort_scale[k]
        e = max(abs(share) - scalars[8], 0.0)
        if share < 0.0:
            e = -e
        eff[k, 0], eff[k, 1], eff[k, 2], eff[k, 3] = cx, cy, cz, e * effort_scale[k]
        squares += e * e
    # The hamstrings' stretch beyond their passive line (effort_joints: knee, hip, lumbar);
    # eff[E, 0] keeps it for the Jacobian.
    knee, hip = effort_joints[0], effort_joints[1]
    stretch = scalars[11] * max(q[hip] - scalars[9] - scalars[10] * q[knee], 0.0)
    eff[effort_joints.shape[0], 0] = stretch
    squares += stretch * stretch
    res[EFFORT_ROW] = math.sqrt(squares)
    tasks = 0.0
    for r in range(ROWS):
        tasks += res[r] * res[r] * weight[r]
    prefs = 0.0
    for j in range(q.shape[0]):
        d = q[j] - limits[2, j]
        prefs += d * d * limits[3, j]
    return 0.5 * (tasks + prefs)


@njit(**JIT)
def jacobian(kin, task, scratch, res, jt):
    """Transposed Jacobian ``jt`` (nq, ROWS) at the posture :func:`residuals` last saw.

    Column j of a point task is axis_j x (point - joint_j); of the palm normal n, axis_j x n;
    of the centre of mass, axis_j x the mass-weighted lever arm of the masses joint j moves.
    Hinge rows (gaze, balance) that hold have zero rows.
    """
    steps, anc, mass_link, mass_geom, joint_child = kin[0], kin[2], kin[4], kin[5], kin[7]
    links, total = task[0], task[2][7]
    effort_joints, relations = task[5], task[7]
    pos, axes, jpos, where, vec = scratch[0], scratch[2], scratch[3], scratch[4], scratch[5]
    eff, sums = scratch[6], scratch[7]
    jt[:, :] = 0.0
    gaze, looking = links[4], res[GAZE_ROW] > 0.0
    out_x, out_y = res[BALANCE_ROW] != 0.0, res[BALANCE_ROW + 1] != 0.0
    effort = res[EFFORT_ROW]
    levers = out_x or out_y or effort > 0.0
    if levers:
        # Each link's subtree: its masses' moment Σ m p and mass Σ m, summed from the leaves
        # up (steps are in tree order), so every joint's lever arm costs O(1) below.
        sums[:, :] = 0.0
        for p in range(mass_link.shape[0]):
            link, m = mass_link[p], mass_geom[p, 3]
            for c in range(3):
                sums[link, c] += m * where[p, c]
            sums[link, 3] += m
        for st in range(steps.shape[0] - 1, -1, -1):
            parent, child = steps[st, 0], steps[st, 1]
            for c in range(4):
                sums[parent, c] += sums[child, c]
    for j in range(jt.shape[0]):
        ax, ay, az = axes[j, 0], axes[j, 1], axes[j, 2]
        for side in range(2):
            grip, hand, row = links[2 * side], links[2 * side + 1], GRIP_ROW[side]
            if anc[grip, j]:
                lx, ly, lz = (pos[grip, 0] - jpos[j, 0], pos[grip, 1] - jpos[j, 1],
                              pos[grip, 2] - jpos[j, 2])
                jt[j, row] = ay * lz - az * ly
                jt[j, row + 1] = az * lx - ax * lz
                jt[j, row + 2] = ax * ly - ay * lx
            if anc[hand, j]:
                nx, ny, nz, row = vec[side, 0], vec[side, 1], vec[side, 2], PALM_ROW[side]
                jt[j, row] = ay * nz - az * ny
                jt[j, row + 1] = az * nx - ax * nz
                jt[j, row + 2] = ax * ny - ay * nx
        if looking and anc[gaze, j]:
            jt[j, GAZE_ROW] = -(vec[2, 0] * ax + vec[2, 1] * ay + vec[2, 2] * az)
        if levers:
            # The subtree's mass-weighted lever arm about joint j, S_j [kg m].
            c = joint_child[j]
            sx = sums[c, 0] - sums[c, 3] * jpos[j, 0]
            sy = sums[c, 1] - sums[c, 3] * jpos[j, 1]
            sz = sums[c, 2] - sums[c, 3] * jpos[j, 2]
            if out_x:
                jt[j, BALANCE_ROW] = (ay * sz - az * sy) / total
            if out_y:
                jt[j, BALANCE_ROW + 1] = (az * sx - ax * sz) / total
            if effort > 0.0:
                # d(sqrt(sum e_J^2)) = sum (e_J g / strength_J) dc_Jz / effort.
                d = 0.0
                for k in range(effort_joints.shape[0]):
                    relation, coef = relations[k, j], eff[k, 3]
                    if relation == 0 or coef == 0.0:
                        continue
                    if relation == 1:  # j below J turns c_J whole: (a_j x c_J)_z
                        d += coef * (ax * eff[k, 1] - ay * eff[k, 0])
                    else:  # j at or above J turns its own subtree: (a_J x (a_j x S_j))_z
                        tx, ty = ay * sz - az * sy, az * sx - ax * sz
                        joint = effort_joints[k]
                        d += coef * (axes[joint, 0] * ty - axes[joint, 1] * tx)
                jt[j, EFFORT_ROW] = d / effort
    stretch = eff[effort_joints.shape[0], 0]
    if stretch > 0.0:  # the hamstrings' term: d(stretch)/d(hip) = stiffness, /d(knee) = -slope x it
        coef = stretch * task[2][11] / effort
        jt[effort_joints[1], EFFORT_ROW] += coef
        jt[effort_joints[0], EFFORT_ROW] -= coef * task[2][10]
