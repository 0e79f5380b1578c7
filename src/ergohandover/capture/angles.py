"""Keypoints -> the Posture columns, by the worksheets' definitions, vectorised over frames.

Every angle is measured in the body's own frames, so a keypoint file may be in any world frame
whose up axis is stated: the *heading* frame (x forward, y to the left, z up) turns with the
hips' left-right line about the vertical; the *thorax* frame has z along the trunk (spine or
mid-hip to the neck base or mid-shoulder point) and y along the shoulder line; the *head* frame
has z along the head (neck base to vertex) or, from the face, x from the ears' midpoint to the
nose and y along the ears; the *hand* frame has z from the hand's centre to the wrist and x
toward the thumb.

- trunk flexion and side bend: the thorax's z from vertical, in the heading frame; trunk twist:
  the thorax turned about its own axis against the hips' line;
- neck flexion and side bend: the head's z in the thorax frame; neck twist: the head turned
  about its axis against the shoulder line (needs the ears);
- knee and elbow flexion: 0 straight (180° minus the included angle);
- upper-arm flexion and abduction: the upper arm's direction in the thorax frame; rotation: the
  forearm's direction about the upper arm in the clavicle's frame, measured only where the
  clavicle is seen and the elbow is bent at least :data:`MIN_ELBOW_FOR_ROTATION_DEG` (a
  straight forearm does not show it);
- shoulder raise: the clavicle's (neck base or clavicle to shoulder) elevation above its neutral
  slope (``neutral_clavicle_deg``: the body model's, a BVH rig's rest pose or a standing frame
  of the capture, per side), + up and − down;
- a column the format declares unseen (``KeypointFormat.unseen``: its source fills those points
  in from a rigid template) is unseen whatever its points say;
- wrist flexion, deviation and twist: the hand frame in the forearm's; the twist (pronation)
  only where the upper arm's rotation is measured;
- hands above the neck, and RULA's "working across the midline or out to the side", from the
  hands (or wrists) as the worker twin computes them.

The joint conventions are the worker twin's (``twin/angles.py``): the same names, signs and
Euler orders, so that the twin's postures measured from its own joint positions come back as
the twin's angles (``tests/test_capture.py``). A column a format cannot measure, or a frame
whose points it needs are missing (NaN), is NaN: unseen.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from ..twin.anthropometry import BodySpec
from .formats import SIDES, KeypointFormat, z_up

MIN_ELBOW_FOR_ROTATION_DEG = 15.0
"""Below this elbow flexion [deg] the upper arm's rotation and the wrist's twist are unseen."""


def clavicle_slope_deg(body: BodySpec) -> float:
    """The clavicle's slope in the y-z plane of the thorax at rest [deg], as ``body``'s twin
    holds it (-17.5 for the ANSUR II 50th-percentile man; -12.6 to -19.4 over the survey's
    bodies and the fixed-ratio twin)."""
    s = body.segments()
    return math.degrees(math.atan2(-s.shoulder_drop, s.clavicle_length))


NEUTRAL_CLAVICLE_DEG = clavicle_slope_deg(BodySpec())
"""The clavicle's slope at rest that shoulder raise is measured from when nothing says the
person's own [deg]."""
ANGLE_DECIMALS = 6
"""Measured angles are rounded to this many decimals [deg]."""
GRIP_REACH_M = 0.10
"""How far a power grip's centre may lie from the wrist [m]: where a format has no hand point,
a hand flag whose wrist is this close to its threshold is unseen (the twin's grip lies 0.4 hand
lengths from the wrist: 7.7 cm for the ANSUR II 50th-percentile man)."""
OUT_TO_SIDE_M = 0.10
"""RULA's lower-arm "+1 out to the side": the hand this far beyond its shoulder [m] (as the
twin's ``OUT_TO_SIDE_M``)."""


def _unit(v: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore", divide="ignore"):
        return v / np.sqrt(_dot(v, v))[..., None]


def _deg(x: np.ndarray) -> np.ndarray:
    return np.degrees(x)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def _in(frame: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(N, 3) world vectors ``v`` in the coordinates of (3, N, 3) frames (``frame[k]``: the
    k-th axis of each, in the world; axes first, so that each is contiguous)."""
    return np.stack([_dot(v, frame[0]), _dot(v, frame[1]), _dot(v, frame[2])], axis=1)


def _frame(z: np.ndarray, across: np.ndarray) -> np.ndarray:
    """(3, N, 3) right-handed frames: z along ``z``, y along ``across`` made normal to z."""
    z = _unit(z)
    y = _unit(across - _dot(across, z)[:, None] * z)
    return np.stack([np.cross(y, z), y, z])


def _frame_x(z: np.ndarray, toward_x: np.ndarray) -> np.ndarray:
    """(3, N, 3) right-handed frames: z along ``z``, x along ``toward_x`` made normal to z."""
    z = _unit(z)
    x = _unit(toward_x - _dot(toward_x, z)[:, None] * z)
    return np.stack([x, np.cross(z, x), z])


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle between (N, 3) vectors [deg]: 0 when they point the same way."""
    return _deg(np.arccos(np.clip(_dot(_unit(a), _unit(b)), -1.0, 1.0)))


def _lean(up: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Flexion (forward) and side bend (to the right) of an up axis, (N, 3) -> deg."""
    up = _unit(up)
    return _deg(np.arctan2(up[:, 0], up[:, 2])), _deg(np.arcsin(np.clip(-up[:, 1], -1, 1)))


def _twist(parent_y: np.ndarray, child: np.ndarray) -> np.ndarray:
    """A child frame's turn about its own z from a parent's left-right axis [deg], the last of
    flexion (y), side bend (x) and twist (about -z), the twin's order."""
    p = _in(child, parent_y)
    return _deg(np.arctan2(-p[:, 0], p[:, 1]))


def _turn(frame: np.ndarray, axis: int, angle: np.ndarray) -> np.ndarray:
    """(3, N, 3) frames turned about their own ``axis`` (0, 1, 2: x, y, z) by ``angle`` [rad]:
    ``frame @ R_axis(angle)``, as two axes mixed (no 3x3 products)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    a, b = {0: (1, 2), 1: (2, 0), 2: (0, 1)}[axis]
    out = frame.copy()
    out[a] = c * frame[a] + s * frame[b]
    out[b] = c * frame[b] - s * frame[a]
    return out


def landmarks(keypoints: np.ndarray, fmt: KeypointFormat, up: str | None = None
              ) -> dict[str, np.ndarray]:
    """Each landmark the format gives, in the heading frame.

    Args:
        keypoints: (N, J, 3) positions in the format's joint order [any length unit].
        fmt: the format.
        up: the up axis of ``keypoints`` (default: the format's).

    Returns:
        Landmark name -> (N, 3), origin at the mid-hip point (or mid-shoulder without hips),
        x forward, y to the left, z up. NaN where a point is missing.
    """
    order, sign = z_up(up or fmt.up)
    p = keypoints[..., order]
    p[..., 2] *= sign
    mark = {name: p[:, fmt.index(joints[0])] if len(joints) == 1
            else p[:, [fmt.index(j) for j in joints]].mean(axis=1)
            for name, joints in fmt.landmarks.items()}
    # Without the hips in a frame, the shoulders give its heading.
    with_hips = np.isfinite(mark["left_hip"] - mark["right_hip"]).all(axis=-1, keepdims=True)
    lateral = np.where(with_hips, mark["left_hip"] - mark["right_hip"],
                       mark["left_shoulder"] - mark["right_shoulder"])
    origin = np.where(with_hips, (mark["left_hip"] + mark["right_hip"]) / 2,
                      (mark["left_shoulder"] + mark["right_shoulder"]) / 2)
    y = _unit(lateral * np.array([1.0, 1.0, 0.0]))
    heading = np.stack([np.cross(y, [0.0, 0.0, 1.0]), y,
                        np.broadcast_to([0.0, 0.0, 1.0], y.shape)])
    return {name: _in(heading, point - origin) for name, point in mark.items()}


def measure(keypoints: np.ndarray, fmt: KeypointFormat, up: str | None = None,
            neutral_clavicle_deg: float | Mapping[str, float] = NEUTRAL_CLAVICLE_DEG
            ) -> dict[str, np.ndarray]:
    """The Posture columns a format's keypoints measure.

    Args:
        keypoints: (N, J, 3) positions in the format's joint order [m].
        fmt: the format.
        up: the up axis of ``keypoints`` (default: the format's).
        neutral_clavicle_deg: the clavicle's slope at rest [deg], one for both sides or
            side -> slope (see :data:`NEUTRAL_CLAVICLE_DEG` and :func:`clavicle_slopes`).

    Returns:
        Column name -> (N,) values: every angle column of the Posture CSV and the flags
        ``hands_above_neck`` and ``{side}_arm_across_midline``; NaN where unseen.
    """
    m = landmarks(np.asarray(keypoints, dtype=np.float64), fmt, up)
    n = len(keypoints)
    nan = np.full((n, 3), np.nan)  # a landmark the format lacks
    hips = m["left_hip"] - m["right_hip"]
    mid_shoulder = (m["left_shoulder"] + m["right_shoulder"]) / 2
    base = m["spine"] if "spine" in m else (m["left_hip"] + m["right_hip"]) / 2
    top = m.get("neck_base", mid_shoulder)
    thorax = _frame(top - base, m["left_shoulder"] - m["right_shoulder"])
    cols: dict[str, np.ndarray] = {}
    cols["trunk_flexion"], cols["trunk_side_bend"] = _lean(thorax[2])
    cols["trunk_twist"] = _twist(hips, thorax)

    if "nose" in m and "left_ear" in m:
        ears = (m["left_ear"] + m["right_ear"]) / 2
        y = _unit(m["left_ear"] - m["right_ear"])
        x = _unit((m["nose"] - ears) - _dot(m["nose"] - ears, y)[:, None] * y)
        face = np.stack([x, y, np.cross(x, y)])
        head_up, head_twist = face[2], _twist(thorax[1], face)
    else:
        head_up = m.get("head_top", nan) - m.get("neck_base", nan)
        head_twist = np.full(n, np.nan)
    cols["neck_flexion"], cols["neck_side_bend"] = _lean(_in(thorax, head_up))
    cols["neck_twist"] = head_twist
    for side in SIDES:
        cols[f"{side}_knee_flexion"] = _angle(m[f"{side}_knee"] - m[f"{side}_hip"],
                                              m[f"{side}_ankle"] - m[f"{side}_knee"])

    grips = {side: m.get(f"{side}_hand", m[f"{side}_wrist"]) for side in SIDES}
    reach = 0.0 if "left_hand" in m else GRIP_REACH_M
    above = np.maximum(grips["left"][:, 2], grips["right"][:, 2]) - top[:, 2]
    cols["hands_above_neck"] = _flag(above > 0, above, 0.0, reach)
    for side, outward in (("left", 1.0), ("right", -1.0)):
        cols.update(_arm(m, side, outward, thorax, top, base, grips[side], reach,
                         neutral_clavicle_deg[side] if isinstance(neutral_clavicle_deg, Mapping)
                         else neutral_clavicle_deg, f"{side}_shoulder_raise" in fmt.unseen))
    for name in fmt.unseen:  # what the format's source fills in rather than measures
        cols[name] = np.full(n, np.nan)
    # To a millionth of a degree, far below any instrument's resolution: a posture exactly on
    # a band edge (a joint at its limit) stays on it through the keypoints' rounding errors.
    return {name: np.round(values, ANGLE_DECIMALS) for name, values in cols.items()}


def clavicle_slopes(keypoints: np.ndarray, fmt: KeypointFormat, up: str | None = None
                    ) -> dict[str, np.ndarray]:
    """Each side's clavicle slope in the thorax's y-z plane [deg], the angle shoulder raise is
    measured from: (N,) per side, NaN where the format does not see it."""
    cols = measure(keypoints, fmt, up, neutral_clavicle_deg=0.0)
    return {side: cols[f"{side}_shoulder_raise"] for side in SIDES}


def _flag(value: np.ndarray, *distances_thresholds_reach) -> np.ndarray:
    """A 0/1 flag, NaN where a point it is decided by is missing or where any of its
    (distance, threshold) pairs lies within ``reach`` of the threshold."""
    *pairs, reach = distances_thresholds_reach
    out = value.astype(float)
    for distance, threshold in zip(pairs[::2], pairs[1::2], strict=True):
        out[~np.isfinite(distance) | (np.abs(distance - threshold) < reach)] = np.nan
    return out


def _arm(m: dict[str, np.ndarray], side: str, outward: float, thorax: np.ndarray,
         neck: np.ndarray, base: np.ndarray, grip: np.ndarray, reach: float,
         neutral_clavicle_deg: float, raise_unseen: bool) -> dict[str, np.ndarray]:
    """One arm's columns (``{side}_...``), in the twin's joint conventions."""
    shoulder, elbow, wrist = (m[f"{side}_{p}"] for p in ("shoulder", "elbow", "wrist"))
    upper, fore = elbow - shoulder, wrist - elbow
    a = _unit(_in(thorax, upper))
    out = {"upper_arm_flexion": _deg(np.arctan2(a[:, 0], -a[:, 2])),
           "upper_arm_abduction": _deg(np.arcsin(np.clip(outward * a[:, 1], -1, 1))),
           "elbow_flexion": _angle(upper, fore)}
    clavicle = _in(thorax, shoulder - m.get(f"{side}_clavicle", neck))
    slope = _deg(np.arctan2(clavicle[:, 2], outward * clavicle[:, 1]))
    out["shoulder_raise"] = (slope - neutral_clavicle_deg + 180.0) % 360.0 - 180.0
    if raise_unseen or (f"{side}_clavicle" not in m and "neck_base" not in m):
        out["shoulder_raise"] = np.full(len(slope), np.nan)
    # The upper arm turns in the clavicle's frame (the twin's joints): its rotation is seen only
    # where the clavicle is and the elbow is bent.
    girdle = _turn(thorax, 0, outward * np.radians(np.nan_to_num(out["shoulder_raise"])))
    d = _unit(_in(girdle, upper))
    arm_frame = _turn(_turn(girdle, 1, -np.arctan2(d[:, 0], -d[:, 2])), 0,
                      np.arcsin(np.clip(d[:, 1], -1, 1)))
    f = _in(arm_frame, fore)
    bent = ((out["elbow_flexion"] >= MIN_ELBOW_FOR_ROTATION_DEG)
            & np.isfinite(out["shoulder_raise"]))
    rotation = -outward * _deg(np.arctan2(f[:, 1], f[:, 0]))
    out["upper_arm_rotation"] = np.where(bent, rotation, np.nan)

    nan = np.full_like(wrist, np.nan)  # a landmark the format lacks
    hand = m.get(f"{side}_hand", nan)
    if f"{side}_index" in m and f"{side}_pinky" in m:
        across = m[f"{side}_index"] - m[f"{side}_pinky"]
    else:
        across = m.get(f"{side}_thumb", nan) - hand
    hand_frame = _frame_x(wrist - hand, across)
    forearm = _turn(_turn(arm_frame, 2, np.radians(-outward * rotation)), 1,
                    -np.radians(out["elbow_flexion"]))
    # Where the rotation is unseen any roll of the forearm does: flexion and deviation (the
    # last two of the three turns) do not depend on it.
    forearm = np.where(bent[None, :, None], forearm, _frame(-fore, _any_normal(fore)))

    def r(i: int, j: int) -> np.ndarray:  # (forearm^T hand)[i, j]
        return _dot(forearm[i], hand_frame[j])

    # The hand in the forearm's frame, the twin's turns: pronation (z), flexion (x), deviation.
    out["wrist_flexion"] = -outward * _deg(np.arcsin(np.clip(r(2, 1), -1, 1)))
    out["wrist_deviation"] = _deg(np.arctan2(-r(2, 0), r(2, 2)))
    out["wrist_twist"] = np.where(bent, -outward * _deg(np.arctan2(-r(0, 1), r(1, 1))), np.nan)

    across = outward * _in(thorax, grip - base)[:, 1]
    beyond = outward * _in(thorax, grip - shoulder)[:, 1]
    out["arm_across_midline"] = _flag((across < 0) | (beyond > OUT_TO_SIDE_M), across, 0.0,
                                      beyond, OUT_TO_SIDE_M, reach)
    return {f"{side}_{name}": values for name, values in out.items()}


def _any_normal(v: np.ndarray) -> np.ndarray:
    """(N, 3) vectors not parallel to ``v`` (to complete a frame whose roll does not matter)."""
    pick = np.where(np.abs(_unit(v)[:, [0]]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    return pick
