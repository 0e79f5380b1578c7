"""Kinematics and tasks of one posture, compiled: what :mod:`.kinematics` and :mod:`.tasks`
compute for N postures at once, written per posture for the numba solver of :mod:`.kernel`.

Why per posture: the solver's kernel runs one location at a time in a few scratch arrays, so
these loops carry no temporaries. The mathematics is that of the numpy modules (same frames,
lever arms, hinge tasks); only the order of the task rows differs, chosen so that the rows a
joint can move form one contiguous range (see :func:`row_touches`):

    rows 0-2 left grip, 3-5 left palm normal, 6-7 balance (x, y), 8 gaze,
    rows 9-11 right grip, 12-14 right palm normal.

Residuals and the Jacobian are separate calls: a trial step that is rejected never needs its
Jacobian, and ``_jacobian`` reuses the scratch ``_residuals`` left (frames, palm normals, the
gaze's turn vector, the masses' positions).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

ROWS = 15
GRIP_ROW, PALM_ROW = (0, 9), (3, 12)  # first row of each side's task
BALANCE_ROW, GAZE_ROW = 6, 8
JIT = {"cache": True, "nogil": True, "error_model": "numpy"}


def row_weights(settings) -> np.ndarray:
    """(ROWS,) task weights in the kernel's row order."""
    hand, palm = [settings.hand] * 3, [settings.palm] * 3
    return np.array([*hand, *palm, settings.balance, settings.balance, settings.gaze,
                     *hand, *palm])


def row_touches(ancestors: np.ndarray, links: np.ndarray, mass_links: np.ndarray) -> np.ndarray:
    """(ROWS, nq) bool: can joint j move task row r? From ``model.ancestors`` (L, nq).

    ``links``: left grip, left hand, right grip, right hand, gaze; ``mass_links`` (P,).
    """
    left_grip, left_hand, right_grip, right_hand, gaze = (ancestors[k] for k in links)
    com = ancestors[mass_links].any(axis=0)
    return np.array([left_grip] * 3 + [left_hand] * 3 + [com] * 2 + [gaze]
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
    pos, rot, axes, jpos, where, vec = scratch
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
    anc, mass_link, mass_geom = kin[2], kin[4], kin[5]
    links, total = task[0], task[2][7]
    pos, axes, jpos, where, vec = scratch[0], scratch[2], scratch[3], scratch[4], scratch[5]
    jt[:, :] = 0.0
    gaze, looking = links[4], res[GAZE_ROW] > 0.0
    out_x, out_y = res[BALANCE_ROW] != 0.0, res[BALANCE_ROW + 1] != 0.0
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
        if out_x or out_y:
            sub_mass, mx, my, mz = 0.0, 0.0, 0.0, 0.0
            for p in range(mass_link.shape[0]):
                if anc[mass_link[p], j]:
                    m = mass_geom[p, 3]
                    sub_mass += m
                    mx += m * where[p, 0]
                    my += m * where[p, 1]
                    mz += m * where[p, 2]
            lx = (mx - sub_mass * jpos[j, 0]) / total
            ly = (my - sub_mass * jpos[j, 1]) / total
            lz = (mz - sub_mass * jpos[j, 2]) / total
            if out_x:
                jt[j, BALANCE_ROW] = ay * lz - az * ly
            if out_y:
                jt[j, BALANCE_ROW + 1] = az * lx - ax * lz
