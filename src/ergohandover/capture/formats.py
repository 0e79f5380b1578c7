"""Keypoint formats as data: each format's joints in its own order, its usual up axis, and which
of its points (or the mean of which) is each landmark the angles are measured from.

A landmark a format lacks is absent, and the Posture columns measured from it are unseen for
that format (:func:`~ergohandover.capture.angles.measure`). The landmarks:

- ``left_hip``/``right_hip`` (hip joint centres), ``left_knee``/``right_knee``,
  ``left_ankle``/``right_ankle``: the legs and the pelvis' left-right axis;
- ``spine`` (a point on the thoracolumbar spine below the neck) and ``neck_base`` (C7/T1, where
  the clavicles meet the spine); without them the trunk runs from the mid-hip to the
  mid-shoulder point;
- ``head_top`` (the vertex, or a head point above the neck on the head's axis), or the face:
  ``nose``, ``left_ear``/``right_ear``;
- ``left_clavicle``/``right_clavicle`` (a point on the clavicle, medial to the shoulder);
- ``left_shoulder``, ``left_elbow``, ``left_wrist`` (joint centres) and the hand: ``left_hand``
  (its centre or the middle knuckle), ``left_thumb``, ``left_index``/``left_pinky``; the same on
  the right.

Joint orders: Human3.6M's 17-joint set as VideoPose3D and MotionBERT give it; COCO's 17
keypoints; MediaPipe Pose's 33 world landmarks; the ZED SDK's BODY_34 (the first 32 in the
Azure Kinect's order, then the heels); SMPL's 24 joints. Up axes: the convention each source
writes (camera frames: y down); a file in another frame takes ``--up``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import ErgohandoverError

SIDES = ("left", "right")
LANDMARKS = (
    "left_hip", "right_hip", "left_knee", "right_knee", "left_ankle", "right_ankle",
    "spine", "neck_base", "head_top", "nose", "left_ear", "right_ear",
    *(f"{side}_{part}" for side in SIDES for part in (
        "clavicle", "shoulder", "elbow", "wrist", "hand", "thumb", "index", "pinky")),
)
"""Every landmark a format may give (the module's text says what each is)."""
UP_AXES = ("x", "-x", "y", "-y", "z", "-z")


class FormatError(ErgohandoverError, ValueError):
    """An unknown format or up axis; the message is one line naming it and what is allowed."""


@dataclass(frozen=True)
class KeypointFormat:
    """One keypoint format.

    Attributes:
        name: what ``--format`` takes.
        title: what it is and where it comes from.
        joints: the format's points, in its own order (a file's J axis).
        up: the axis that points up in the frame the format is usually written in.
        landmarks: landmark -> the joint names whose mean is it.
        unseen: Posture columns its points do not show although their geometry would: points
            its source fills in from a rigid template rather than measures.
        body: the joints whose extent is the body's for the size checks (empty: every joint;
            a BVH file's props, fingers and toes are not).
        rest: every joint's position in the rig's rest pose (a BVH file's OFFSETs with no
            rotation), the body's own neutral; empty for formats without one.
    """

    name: str
    title: str
    joints: tuple[str, ...]
    up: str
    landmarks: dict[str, tuple[str, ...]] = field(hash=False)
    unseen: tuple[str, ...] = ()
    body: tuple[str, ...] = ()
    rest: tuple[tuple[float, float, float], ...] = field(default=(), hash=False, compare=False)

    def __post_init__(self):
        for landmark, names in self.landmarks.items():
            unknown = [n for n in names if n not in self.joints]
            if landmark not in LANDMARKS or unknown:
                raise ValueError(f"{self.name}: landmark {landmark} from {names}")
        if not set(self.body) <= set(self.joints):
            raise ValueError(f"{self.name}: body joints {set(self.body) - set(self.joints)}")

    def index(self, joint: str) -> int:
        return self.joints.index(joint)


def _sided(**parts: str) -> dict[str, tuple[str, ...]]:
    """Landmarks of both sides from ``part=joint pattern`` ({side}, {s} for l/r, {S} for L/R)."""
    out = {}
    for side in SIDES:
        for part, pattern in parts.items():
            out[f"{side}_{part}"] = tuple(
                p.format(side=side, s=side[0], S=side[0].upper(), SIDE=side.upper())
                for p in pattern.split("+"))
    return out


H36M_17 = KeypointFormat(
    "h36m17", "Human3.6M's 17 joints (VideoPose3D, MotionBERT)",
    ("pelvis", "right_hip", "right_knee", "right_ankle", "left_hip", "left_knee",
     "left_ankle", "spine", "thorax", "neck_nose", "head", "left_shoulder", "left_elbow",
     "left_wrist", "right_shoulder", "right_elbow", "right_wrist"),
    "-y",
    {"spine": ("spine",), "neck_base": ("thorax",), "head_top": ("head",),
     **_sided(hip="{side}_hip", knee="{side}_knee", ankle="{side}_ankle",
              shoulder="{side}_shoulder", elbow="{side}_elbow", wrist="{side}_wrist")},
)

COCO_17 = KeypointFormat(
    "coco17", "COCO's 17 keypoints, lifted to 3D",
    ("nose", "left_eye", "right_eye", "left_ear", "right_ear", "left_shoulder",
     "right_shoulder", "left_elbow", "right_elbow", "left_wrist", "right_wrist", "left_hip",
     "right_hip", "left_knee", "right_knee", "left_ankle", "right_ankle"),
    "-y",
    {"nose": ("nose",),
     **_sided(ear="{side}_ear", hip="{side}_hip", knee="{side}_knee", ankle="{side}_ankle",
              shoulder="{side}_shoulder", elbow="{side}_elbow", wrist="{side}_wrist")},
)

MEDIAPIPE_33 = KeypointFormat(
    "mediapipe33", "MediaPipe Pose's 33 world landmarks (metres, origin at the hips' centre)",
    ("nose", "left_eye_inner", "left_eye", "left_eye_outer", "right_eye_inner", "right_eye",
     "right_eye_outer", "left_ear", "right_ear", "mouth_left", "mouth_right", "left_shoulder",
     "right_shoulder", "left_elbow", "right_elbow", "left_wrist", "right_wrist", "left_pinky",
     "right_pinky", "left_index", "right_index", "left_thumb", "right_thumb", "left_hip",
     "right_hip", "left_knee", "right_knee", "left_ankle", "right_ankle", "left_heel",
     "right_heel", "left_foot_index", "right_foot_index"),
    "-y",
    {"nose": ("nose",),
     **_sided(ear="{side}_ear", hip="{side}_hip", knee="{side}_knee", ankle="{side}_ankle",
              shoulder="{side}_shoulder", elbow="{side}_elbow", wrist="{side}_wrist",
              hand="{side}_index+{side}_pinky", thumb="{side}_thumb", index="{side}_index",
              pinky="{side}_pinky")},
)

ZED_34 = KeypointFormat(
    "zed34", "the ZED SDK's BODY_34 (Stereolabs)",
    ("pelvis", "naval_spine", "chest_spine", "neck", "left_clavicle", "left_shoulder",
     "left_elbow", "left_wrist", "left_hand", "left_handtip", "left_thumb", "right_clavicle",
     "right_shoulder", "right_elbow", "right_wrist", "right_hand", "right_handtip",
     "right_thumb", "left_hip", "left_knee", "left_ankle", "left_foot", "right_hip",
     "right_knee", "right_ankle", "right_foot", "head", "nose", "left_eye", "left_ear",
     "right_eye", "right_ear", "left_heel", "right_heel"),
    "z",
    {"spine": ("chest_spine",), "neck_base": ("neck",), "nose": ("nose",),
     **_sided(ear="{side}_ear", hip="{side}_hip", knee="{side}_knee", ankle="{side}_ankle",
              clavicle="{side}_clavicle", shoulder="{side}_shoulder", elbow="{side}_elbow",
              wrist="{side}_wrist", hand="{side}_hand", thumb="{side}_thumb")},
    # The SDK fits a skeleton whose shoulder girdle and hands are rigid: over Kim et al.'s
    # 1,000 recordings (ICRA 2025) the clavicle's slope and the hand's angles to the forearm
    # never change (SD 0.00 deg), so shoulder raise and the wrist are not measured.
    unseen=tuple(f"{side}_{column}" for side in SIDES for column in (
        "shoulder_raise", "wrist_flexion", "wrist_deviation", "wrist_twist")),
)

SMPL_24 = KeypointFormat(
    "smpl24", "SMPL's 24 joints",
    ("pelvis", "left_hip", "right_hip", "spine1", "left_knee", "right_knee", "spine2",
     "left_ankle", "right_ankle", "spine3", "left_foot", "right_foot", "neck", "left_collar",
     "right_collar", "head", "left_shoulder", "right_shoulder", "left_elbow", "right_elbow",
     "left_wrist", "right_wrist", "left_hand", "right_hand"),
    "y",
    {"spine": ("spine3",), "neck_base": ("neck",), "head_top": ("head",),
     **_sided(hip="{side}_hip", knee="{side}_knee", ankle="{side}_ankle",
              clavicle="{side}_collar", shoulder="{side}_shoulder", elbow="{side}_elbow",
              wrist="{side}_wrist", hand="{side}_hand")},
)

FORMATS: dict[str, KeypointFormat] = {f.name: f for f in (
    H36M_17, COCO_17, MEDIAPIPE_33, ZED_34, SMPL_24)}
"""Every keypoint format by its ``--format`` name (BVH files bring their own joints:
:mod:`~ergohandover.capture.bvh`)."""


def keypoint_format(name: str) -> KeypointFormat:
    """The format called ``name``; :class:`FormatError` naming the known ones otherwise."""
    try:
        return FORMATS[name]
    except KeyError:
        raise FormatError(f"format {name!r} is not known (use {', '.join(FORMATS)})") \
            from None


def z_up(up: str) -> tuple[list[int], float]:
    """How a frame whose up axis is ``up`` (``x``, ``-y``, …) becomes a right-handed z-up one:
    ``z_up_points = points[..., order] * (1, 1, sign)``; returns (order, sign)."""
    if up not in UP_AXES:
        raise FormatError(f"up axis {up!r} is not allowed (use {', '.join(UP_AXES)})")
    axis, sign = "xyz".index(up[-1]), -1.0 if up.startswith("-") else 1.0
    a, b = (axis + 1) % 3, (axis + 2) % 3
    return ([a, b, axis] if sign > 0 else [b, a, axis]), sign
