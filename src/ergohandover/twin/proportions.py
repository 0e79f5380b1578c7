"""How a body's measurements become the twin's joint heights and segment lengths.

Two proportion models:

* ``ansur2`` (the default): every landmark the ANSUR II survey measures is the person's own
  (given, or filled in by the fitted body model, :mod:`~ergohandover.twin.body_model`): ankle,
  knee, hip, shoulder and wrist heights, upper arm, hand and foot lengths, shoulder and hip
  breadths. The joints the survey cannot reach (L5/S1, C7/T1, the head-neck joint) sit at a
  fixed offset from the nearest surveyed landmark (iliac crest, cervicale, ear canal).
* ``drillis-contini``: the fixed-ratio twin, every length a fixed fraction of stature (Drillis &
  Contini 1966 as tabulated by Winter 2009, plus the estimates marked below), so a body's
  proportions never vary; kept to show what the survey's proportions change.

Both give the same :data:`JOINT_NAMES`; :func:`segments_from_joints` builds the segments from
them. Everything is elementwise, so arrays of people are checked in one call.
"""

from __future__ import annotations

import numpy as np

PROPORTIONS = ("ansur2", "drillis-contini")

# The fixed-ratio twin's landmarks [fraction of stature]: Drillis & Contini / Winter (2009) unless
# marked as an estimate.
RATIOS = {
    "ankle_height_m": 0.039,
    "knee_height_m": 0.285,
    "hip_height_m": 0.530,  # greater trochanter, taken as the joint
    "lumbar_joint_height_m": 0.585,  # estimate: L5/S1 about one vertebra below the iliac crests
    "neck_joint_height_m": 0.855,  # estimate: C7/T1 a little below the cervicale landmark
    "head_joint_height_m": 0.914,  # estimate: atlanto-occipital joint below the ear canal
    "shoulder_height_m": 0.818,
    "upper_arm_length_m": 0.186,
    "forearm_length_m": 0.146,
    "hand_length_m": 0.108,
    "foot_length_m": 0.152,
    "foot_breadth_m": 0.055,
    "shoulder_width_m": 0.210,  # estimate: biacromial ~0.226 minus the joint centres' inset
    "hip_width_m": 0.095,  # estimate after Bell et al. (1990): hip centres ~0.36 IAD from midline
}

# Offsets from a surveyed landmark to a joint the survey does not measure [fraction of stature].
# They keep the fixed-ratio twin's estimates where the survey's landmark now stands: at the
# survey's male means (iliac crest 0.604, cervicale 0.864, ear canal 0.925 of stature) they put
# the joints at the earlier 0.585, 0.855 and 0.914.
LUMBAR_BELOW_ILIAC_CREST = 0.019  # L5/S1 about one vertebra below the crests (L4/L5 level)
NECK_BELOW_CERVICALE = 0.009  # C7/T1 joint below the C7 spinous process's skin mark
HEAD_JOINT_BELOW_EAR_CANAL = 0.012  # atlanto-occipital joint below the tragion
JOINT_INSET_FROM_ACROMIA = 0.016  # shoulder joint centres inside the biacromial breadth
HIP_WIDTH_PER_HIP_BREADTH = 0.482  # hip centres' spacing per hip breadth: the earlier 0.095 of
# stature at the survey's male mean hip breadth (0.197 of stature)

JOINT_NAMES = ("ankle_height_m", "knee_height_m", "hip_height_m", "lumbar_joint_height_m",
               "neck_joint_height_m", "head_joint_height_m", "shoulder_height_m",
               "elbow_joint_height_m", "wrist_height_m", "upper_arm_length_m",
               "forearm_length_m", "hand_length_m", "foot_length_m", "foot_breadth_m",
               "shoulder_width_m", "hip_width_m")
"""What a proportion model gives: joint heights above the floor and lengths [m]."""

ORDER = (("elbow_height_m", "shoulder_height_m"), ("elbow_joint_height_m", "shoulder_height_m"),
         ("wrist_height_m", "elbow_joint_height_m"), ("ankle_height_m", "knee_height_m"),
         ("knee_height_m", "hip_height_m"),
         ("hip_height_m", "lumbar_joint_height_m"),
         ("lumbar_joint_height_m", "neck_joint_height_m"),
         ("neck_joint_height_m", "head_joint_height_m"), ("head_joint_height_m", "stature_m"),
         ("shoulder_height_m", "neck_joint_height_m"), ("hip_height_m", "shoulder_height_m"))
"""Pairs (lower, upper) of heights a body must have in this order."""


def ratio_landmarks(stature):
    """The fixed-ratio twin's landmarks of a body of ``stature`` [m] (a number or an array)."""
    out = {name: fraction * stature for name, fraction in RATIOS.items()}
    out["stature_m"] = stature
    out["elbow_joint_height_m"] = out["shoulder_height_m"] - out["upper_arm_length_m"]
    # The fixed-ratio twin has no separate bent-elbow landmark: its elbow height is the joint's.
    out["elbow_height_m"] = out["elbow_joint_height_m"]
    out["wrist_height_m"] = out["elbow_joint_height_m"] - out["forearm_length_m"]
    out["arm_length_m"] = out["shoulder_height_m"] - out["wrist_height_m"]
    return out


def survey_landmarks(values: dict):
    """Joint heights and lengths from the survey's measurements (numbers or arrays, keyed by
    :data:`~ergohandover.twin.body_model.MEASUREMENTS` names), with the derived quantities."""
    out = dict(values)
    h = values["stature_m"]
    out["lumbar_joint_height_m"] = values["iliac_crest_height_m"] - LUMBAR_BELOW_ILIAC_CREST * h
    out["neck_joint_height_m"] = values["cervicale_height_m"] - NECK_BELOW_CERVICALE * h
    out["head_joint_height_m"] = h - values["ear_to_vertex_m"] - HEAD_JOINT_BELOW_EAR_CANAL * h
    out["elbow_joint_height_m"] = values["shoulder_height_m"] - values["upper_arm_length_m"]
    out["elbow_height_m"] = values["shoulder_height_m"] - values["shoulder_elbow_length_m"]
    out["forearm_length_m"] = out["elbow_joint_height_m"] - values["wrist_height_m"]
    out["arm_length_m"] = values["shoulder_height_m"] - values["wrist_height_m"]
    out["shoulder_width_m"] = values["shoulder_breadth_m"] - JOINT_INSET_FROM_ACROMIA * h
    out["hip_width_m"] = HIP_WIDTH_PER_HIP_BREADTH * values["hip_breadth_m"]
    return out


def disorder(landmarks: dict) -> tuple[str, str] | None:
    """The first pair of :data:`ORDER` a body breaks, or None (one body, plain numbers)."""
    for lower, upper in ORDER:
        if not landmarks[lower] < landmarks[upper]:
            return lower, upper
    return None


def in_order(landmarks: dict) -> np.ndarray:
    """Whether each body of arrays of landmarks keeps :data:`ORDER` and positive lengths."""
    ok = np.ones(np.shape(landmarks["stature_m"]), dtype=bool)
    for lower, upper in ORDER:
        ok &= landmarks[lower] < landmarks[upper]
    for name in ("forearm_length_m", "shoulder_width_m", "hip_width_m", "ankle_height_m"):
        ok &= landmarks[name] > 0
    return ok


# Segment sizes that no proportion model measures [fraction of stature], as in the fixed-ratio twin.
EYE_ABOVE_HEAD_JOINT = 0.936 - 0.914  # Drillis & Contini / Winter eye level, above the joint
SHAPE_FRACTIONS = {
    "eye_forward": 0.050,  # estimate: cornea ~9 cm in front of the occipital condyles
    # Collision/visual sizes. Widths are kept below the real chest and hip breadths so that
    # hanging arms clear the trunk and pelvis shapes and the thighs clear the hands.
    "trunk_depth": 0.130,  # ~chest depth (ANSUR ~0.14)
    "trunk_width": 0.150,
    "pelvis_width": 0.160,  # Winter's hip breadth is 0.191; narrowed as said above
    "head_radius": 0.052,  # head circumference ~0.325 of stature / 2 pi
    "upper_arm_radius": 0.026,
    "forearm_radius": 0.020,
    "thigh_radius": 0.036,
    "shank_radius": 0.028,
}
GRIP_PER_HAND = 0.40  # estimate: a fist closes round a handle ~0.4 down the hand
HEEL_PER_FOOT = 0.22  # estimate: malleoli ~1/5 of the foot from the heel


def segment_sizes(joints: dict) -> dict[str, float]:
    """The twin's segment lengths and shape sizes [m] (the fields of ``Segments``) from a
    body's joint heights and lengths."""
    h = joints["stature_m"]
    vertical = ("ankle_height_m", "knee_height_m", "hip_height_m", "lumbar_joint_height_m",
                "neck_joint_height_m", "head_joint_height_m", "stature_m")
    names = ("ankle_height", "shank_length", "thigh_length", "pelvis_height", "trunk_length",
             "neck_length", "head_height")
    tops = [joints[n] for n in vertical]
    sizes = {name: top - bottom for name, top, bottom in zip(names, tops, [0.0, *tops[:-1]],
                                                             strict=True)}
    sizes |= {
        "shoulder_drop": joints["neck_joint_height_m"] - joints["shoulder_height_m"],
        "eye_height_above_head_joint": EYE_ABOVE_HEAD_JOINT * h,
        "hip_width": joints["hip_width_m"],
        "shoulder_width": joints["shoulder_width_m"],
        "clavicle_length": joints["shoulder_width_m"] / 2.0,
        "upper_arm_length": joints["upper_arm_length_m"],
        "forearm_length": joints["forearm_length_m"],
        "hand_length": joints["hand_length_m"],
        "grip_offset": GRIP_PER_HAND * joints["hand_length_m"],
        "foot_length": joints["foot_length_m"],
        "foot_width": joints["foot_breadth_m"],
        "heel_to_ankle": HEEL_PER_FOOT * joints["foot_length_m"],
    }
    return sizes | {name: fraction * h for name, fraction in SHAPE_FRACTIONS.items()}
