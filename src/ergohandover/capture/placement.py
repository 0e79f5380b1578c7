"""The worker twin's body points placed as each keypoint format places its joints: the twin's own
postures as a camera or motion capture would report them, for the round trips that check the
capture layer and for the example files.

Every format joint is a point fixed in one of the twin's links (joint centres at the twin's
joints; the face, hands and feet at points of its shapes). Points a format gives but the angles
do not use (eyes, mouth, heels, toes, hand tips) are placed where the twin's shapes put them,
so that files look like the formats' own.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..twin.anthropometry import BodySpec, Segments
from ..twin.kinematics import KinematicState
from .formats import SIDES, KeypointFormat, z_up

Offset = Callable[[Segments, float], tuple[float, float, float]]
"""A point's offset in its link's frame [m] from the body's segments and the side's sign (+1
left, -1 right; 0 for points on the mid-line)."""


def _head(s: Segments) -> float:
    """Height of the eyes (and ears, nose) above the neck joint, in the head's frame [m]."""
    return s.neck_length + s.eye_height_above_head_joint


def _breadth(s: Segments) -> float:
    """The hand's breadth across the knuckles [m] (the twin's hand box)."""
    return 2.4 * s.forearm_radius


POINTS: dict[str, tuple[str, Offset]] = {
    "pelvis": ("pelvis", lambda s, k: (0.0, 0.0, 0.0)),
    "hip": ("pelvis", lambda s, k: (0.0, k * s.hip_width / 2, 0.0)),
    "knee": ("thigh", lambda s, k: (0.0, k * s.hip_width / 2, 0.0)),
    "ankle": ("shank", lambda s, k: (0.0, k * s.hip_width / 2, 0.0)),
    "heel": ("feet", lambda s, k: (-s.heel_to_ankle, k * s.hip_width / 2, 0.0)),
    "toe": ("feet", lambda s, k: (0.73 * s.foot_length - s.heel_to_ankle, k * s.hip_width / 2,
                                  0.0)),
    "spine_low": ("thorax", lambda s, k: (0.0, 0.0, 0.1 * s.trunk_length)),
    "spine_mid": ("thorax", lambda s, k: (0.0, 0.0, 0.4 * s.trunk_length)),
    "spine_high": ("thorax", lambda s, k: (0.0, 0.0, 0.7 * s.trunk_length)),
    "neck_base": ("thorax", lambda s, k: (0.0, 0.0, s.trunk_length)),
    "head_joint": ("head", lambda s, k: (0.0, 0.0, s.neck_length)),
    "head_centre": ("head", lambda s, k: (0.0, 0.0, s.neck_length + s.head_height
                                         - s.head_radius)),
    "head_top": ("head", lambda s, k: (0.0, 0.0, s.neck_length + s.head_height)),
    "nose": ("head", lambda s, k: (s.head_radius, 0.0, _head(s))),
    "ear": ("head", lambda s, k: (0.0, k * s.head_radius, _head(s))),
    "eye": ("head", lambda s, k: (0.8 * s.head_radius, k * 0.35 * s.head_radius, _head(s))),
    "eye_inner": ("head", lambda s, k: (0.9 * s.head_radius, k * 0.2 * s.head_radius,
                                        _head(s))),
    "eye_outer": ("head", lambda s, k: (0.7 * s.head_radius, k * 0.5 * s.head_radius,
                                        _head(s))),
    "mouth": ("head", lambda s, k: (0.85 * s.head_radius, k * 0.25 * s.head_radius,
                                    _head(s) - 0.6 * s.head_radius)),
    "clavicle": ("clavicle", lambda s, k: (0.0, k * s.clavicle_length / 2,
                                           -s.shoulder_drop / 2)),
    "shoulder": ("shoulder_flexion_link", lambda s, k: (0.0, 0.0, 0.0)),
    "elbow": ("forearm", lambda s, k: (0.0, 0.0, 0.0)),
    "wrist": ("wrist_flexion_link", lambda s, k: (0.0, 0.0, 0.0)),
    "hand": ("hand", lambda s, k: (0.0, 0.0, -s.grip_offset)),  # a power grip's centre
    "handtip": ("hand", lambda s, k: (0.0, 0.0, -s.hand_length)),
    "thumb": ("hand", lambda s, k: (0.5 * _breadth(s), 0.0, -0.3 * s.hand_length)),
    "index": ("hand", lambda s, k: (0.35 * _breadth(s), 0.0, -s.grip_offset)),
    "pinky": ("hand", lambda s, k: (-0.35 * _breadth(s), 0.0, -s.grip_offset)),
}
"""Each twin point: its link (arm links without their side prefix) and offset."""
ARM_LINKS = {"clavicle", "shoulder_flexion_link", "forearm", "wrist_flexion_link", "hand"}

FORMAT_POINTS: dict[str, dict[str, str]] = {
    "h36m17": {"spine": "spine_mid", "thorax": "neck_base", "neck_nose": "head_joint",
               "head": "head_top"},
    "coco17": {},
    "mediapipe33": {"left_foot_index": "left_toe", "right_foot_index": "right_toe",
                    "mouth_left": "left_mouth", "mouth_right": "right_mouth"},
    "zed34": {"naval_spine": "spine_mid", "chest_spine": "spine_high", "neck": "neck_base",
              "head": "head_centre", "left_foot": "left_toe", "right_foot": "right_toe"},
    "smpl24": {"spine1": "spine_low", "spine2": "spine_mid", "spine3": "spine_high",
               "neck": "neck_base", "head": "head_centre", "left_collar": "left_clavicle",
               "right_collar": "right_clavicle", "left_foot": "left_toe",
               "right_foot": "right_toe"},
}
"""Where a format joint is not the twin point of the same name: the twin point it is."""


def twin_point(name: str) -> tuple[str, str | None]:
    """(point, side) of a sided (``left_elbow``) or mid-line (``nose``) twin point name."""
    for side in SIDES:
        if name.startswith(f"{side}_"):
            return name.removeprefix(f"{side}_"), side
    return name, None


def place(state: KinematicState, body: BodySpec, fmt: KeypointFormat,
          up: str | None = None) -> np.ndarray:
    """The twin's points of N solved postures as ``fmt``'s joints.

    Args:
        state: forward kinematics of the postures (the twin's world: x forward, y left, z up).
        body: the body the skeleton was built from.
        fmt: the format.
        up: the up axis to write them with (default: the format's own).

    Returns:
        (N, J, 3) positions [m] in the format's joint order.
    """
    s = body.segments()
    points = []
    for joint in fmt.joints:
        point, side = twin_point(FORMAT_POINTS[fmt.name].get(joint, joint))
        link, offset = POINTS[point]
        if link in ARM_LINKS:
            link = f"{side}_{link}"
        sign = {"left": 1.0, "right": -1.0, None: 0.0}[side]
        points.append(state.point(link, offset(s, sign)))
    return to_axes(np.stack(points, axis=1), up or fmt.up)


def to_axes(points: np.ndarray, up: str) -> np.ndarray:
    """(..., 3) points of a z-up frame written in a frame whose up axis is ``up`` (the inverse of
    the turn :func:`~ergohandover.capture.angles.landmarks` makes)."""
    order, sign = z_up(up)
    out = np.empty_like(points)
    out[..., order] = points * np.array([1.0, 1.0, sign])
    return out
