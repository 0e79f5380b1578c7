"""Static low-back load at L5/S1 and the arms' joint moments, from a posture, a body and the load.

The sagittal-plane static model of occupational biomechanics (the form of Chaffin's simple
low-back model, Chaffin, Andersson & Martin, *Occupational Biomechanics*): the body above
L5/S1 is a chain — trunk at its flexion from vertical, head and neck, and each arm's upper arm,
forearm and hand at their flexion angles — each segment's weight at its centre of mass, and
the box's weight shared equally by the two grips. Gravity's moment about L5/S1 must be held
by the back extensors acting :data:`ERECTOR_ARM_M` behind the joint, so

    compression = |M| / 0.05 m + (weight above L5/S1 + load) cos(trunk flexion)
    shear       = (weight above L5/S1 + load) sin(trunk flexion)

(the 5 cm arm and this form are those of the public static sagittal implementations read,
none citing a page; no abdominal-pressure term). Segment lengths, masses and centres of mass
are the body model's (Winter's fractions,
:meth:`~ergohandover.twin.anthropometry.BodySpec.segment_masses`).

Its stated limits: static (no acceleration), sagittal plane only (side bend, twist and
abduction are not seen; the arm is taken in the sagittal plane), symmetric two-handed load.
For the twin's own mid-sagittal postures its lumbar moment is the twin's 3-D one to within 4 %
(tests/test_workload.py).
The compression is compared with NIOSH's design limit of 3,400 N and upper limit of 6,400 N
(NIOSH 1981, Work Practices Guide for Manual Lifting, Pub. 81-122: 350 kg and 650 kg).

Strength: the share of the body's mean torso extension strength the lumbar moment takes (the
twin's strength, :meth:`~ergohandover.twin.anthropometry.BodySpec.joint_strengths_nm`), and
"% capable", the share of people of that size whose strength exceeds it, taking strength as
normal with a coefficient of variation of :data:`STRENGTH_CV` (an assumed constant, the one of
La Delfa & Potvin's Arm Force Field code, 2017; no population SD of torso strength was read).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr

from ..ergonomics import Posture
from ..ergonomics.posture import SIDES
from ..twin.anthropometry import GRAVITY, BodySpec

ERECTOR_ARM_M = 0.05
"""The back extensors' moment arm about L5/S1 [m]."""
COMPRESSION_LIMITS_N = (3400.0, 6400.0)
"""NIOSH's design (action) limit and upper (maximum permissible) limit of L5/S1 compression."""
STRENGTH_CV = 0.277
"""Coefficient of variation of joint strength (an assumption, see the module's text)."""

COLUMNS = ("back_moment_nm", "back_compression_n", "back_shear_n", "back_band",
           "back_strength_share", "back_capable_pct", "shoulder_moment_nm", "elbow_moment_nm")
"""The columns :func:`back_load` gives: the lumbar moment, compression, shear, the band of the
compression (0 below the design limit, 1 up to the upper limit, 2 above), the moment's share of
mean strength and % capable, and the larger side's shoulder and elbow moments."""


@dataclass(frozen=True)
class Levers:
    """What the model needs of a body: lengths [m], masses [kg], centres of mass [fraction of
    the segment from its proximal end] and mean torso extension strength [N m]."""

    trunk: tuple[float, float, float]
    head: tuple[float, float, float]
    shoulder_drop: float
    upper_arm: tuple[float, float, float]
    forearm: tuple[float, float, float]
    hand: tuple[float, float, float]
    grip_offset: float
    lumbar_strength_nm: float

    @classmethod
    def of(cls, body: BodySpec) -> Levers:
        """The levers of a body of the twin's model."""
        s, m = body.segments(), body.segment_masses()

        def seg(name: str, length: float) -> tuple[float, float, float]:
            return (length, m[name].mass_kg, m[name].com_fraction)

        return cls(trunk=seg("trunk", s.trunk_length),
                   head=seg("head_neck", s.neck_length + s.head_height),
                   shoulder_drop=s.shoulder_drop,
                   upper_arm=seg("upper_arm", s.upper_arm_length),
                   forearm=seg("forearm", s.forearm_length), hand=seg("hand", s.hand_length),
                   grip_offset=s.grip_offset,
                   lumbar_strength_nm=body.joint_strengths_nm()["lumbar_flexion"])


def _forward(angle_deg: np.ndarray) -> np.ndarray:
    return np.sin(np.radians(angle_deg))


def _arm(p: Posture, side: str, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One arm's upper arm and forearm angles from the vertical [deg]. Down-pointing segments
    turn against the trunk's lean: an arm flexed as far as the trunk is bent hangs straight
    down."""
    upper = p.arm(side, "upper_arm_flexion") - theta
    return upper, upper + p.arm(side, "elbow_flexion")


def grip_reach_m(p: Posture, levers: Levers) -> np.ndarray:
    """How far forward of L5/S1 the hands hold the load [m], the two grips' mean: the
    horizontal lever of the load in the same sagittal chain as :func:`back_load`."""
    theta = p["trunk_flexion"]
    shoulder_x = (levers.trunk[0] - levers.shoulder_drop) * _forward(theta)
    reach = []
    for side in SIDES:
        upper, fore = _arm(p, side, theta)
        reach.append(shoulder_x + levers.upper_arm[0] * _forward(upper)
                     + (levers.forearm[0] + levers.grip_offset) * _forward(fore))
    return (reach[0] + reach[1]) / 2.0


def back_load(p: Posture, levers: Levers) -> dict[str, np.ndarray]:
    """Every column of :data:`COLUMNS` for N postures (float arrays; ``back_band`` int8)."""
    trunk_len, trunk_kg, trunk_com = levers.trunk
    head_len, head_kg, head_com = levers.head
    theta = p["trunk_flexion"]
    lean = _forward(theta)
    # Horizontal distance forward of L5/S1 of each weight, times its mass.
    moment = trunk_kg * trunk_com * trunk_len * lean
    moment += head_kg * (trunk_len * lean + head_com * head_len
                         * _forward(theta + p["neck_flexion"]))
    shoulder_x = (trunk_len - levers.shoulder_drop) * lean
    half_load = p["load_kg"] / 2.0
    arm_kg = sum(getattr(levers, k)[1] for k in ("upper_arm", "forearm", "hand"))
    shoulder_nm, elbow_nm = [], []
    for side in SIDES:
        upper, fore = _arm(p, side, theta)
        ua_len, ua_kg, ua_com = levers.upper_arm
        fa_len, fa_kg, fa_com = levers.forearm
        hand_len, hand_kg, hand_com = levers.hand
        elbow = ua_len * _forward(upper)  # from the shoulder
        # About the elbow: forearm, hand and the grip's share of the load.
        about_elbow = _forward(fore) * (fa_kg * fa_com * fa_len
                                        + hand_kg * (fa_len + hand_com * hand_len)
                                        + half_load * (fa_len + levers.grip_offset))
        about_shoulder = about_elbow + elbow * (fa_kg + hand_kg + half_load) \
            + ua_kg * ua_com * ua_len * _forward(upper)
        elbow_nm.append(np.abs(about_elbow) * GRAVITY)
        shoulder_nm.append(np.abs(about_shoulder) * GRAVITY)
        moment = moment + about_shoulder + shoulder_x * (arm_kg + half_load)
    moment = moment * GRAVITY
    weight = GRAVITY * (trunk_kg + head_kg + 2 * arm_kg + p["load_kg"])
    compression = np.abs(moment) / ERECTOR_ARM_M + weight * np.cos(np.radians(theta))
    shear = weight * np.abs(np.sin(np.radians(theta)))
    strength = levers.lumbar_strength_nm
    share = np.abs(moment) / strength
    capable = 100.0 * ndtr((1.0 - share) / STRENGTH_CV)
    return {"back_moment_nm": moment, "back_compression_n": compression, "back_shear_n": shear,
            "back_band": np.searchsorted(COMPRESSION_LIMITS_N, compression).astype(np.int8),
            "back_strength_share": share, "back_capable_pct": capable,
            "shoulder_moment_nm": np.maximum(*shoulder_nm),
            "elbow_moment_nm": np.maximum(*elbow_nm)}
