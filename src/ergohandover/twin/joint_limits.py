"""The joints' ranges of motion, and how a worker's may be narrower: restrictions and the
impairments made of them.

An impaired worker is a joint whose range is restricted, one at a time on the right arm (the
box is held in both hands, so one arm limits the whole reach): a shoulder that cannot flex past
90° (a stiff or painful shoulder), an elbow that lacks 30° of extension (a flexion
contracture), a wrist that cannot flex (:data:`IMPAIRMENTS`). The twin's solver keeps every
joint within its limits, so an impaired twin takes the box with the rest of its body.
"""

from __future__ import annotations

import dataclasses
import math
import numbers

# Range of motion [deg] as (lower, upper), positive in the direction the name says. AAOS (1965)
# unless noted. Trunk flexion is shared by the hip and lumbar joints, so the lumbar joint gets
# the spine's own share (Kapandji: ~60 deg lumbar flexion), not the whole-trunk range.
AXIAL_LIMITS_DEG = {
    "ankle_flexion": (-50.0, 20.0),  # plantarflexion 50, dorsiflexion 20
    "knee_flexion": (0.0, 135.0),
    "hip_flexion": (-30.0, 120.0),
    "lumbar_flexion": (-25.0, 60.0),  # extension 25 (AAOS thoracolumbar), flexion: Kapandji
    "lumbar_side_bend": (-35.0, 35.0),
    "lumbar_twist": (-45.0, 45.0),
    "neck_flexion": (-45.0, 45.0),
    "neck_side_bend": (-45.0, 45.0),
    "neck_twist": (-60.0, 60.0),
}
ARM_LIMITS_DEG = {
    "clavicle_elevation": (-10.0, 35.0),  # estimate: shoulder-girdle shrug at the SC joint
    "shoulder_flexion": (-60.0, 180.0),
    "shoulder_abduction": (-30.0, 180.0),  # adduction across the body: Kapandji 30-45
    "shoulder_rotation": (-90.0, 70.0),  # external 90, internal 70
    "elbow_flexion": (0.0, 150.0),
    "forearm_pronation": (-80.0, 80.0),  # supination 80, pronation 80
    "wrist_flexion": (-70.0, 80.0),  # extension 70, flexion 80
    "wrist_deviation": (-20.0, 30.0),  # radial 20, ulnar 30
}



def default_joint_limits_deg() -> dict[str, tuple[float, float]]:
    """Every joint's default range [deg]: the axial joints', and each arm joint's with
    ``left_`` and ``right_`` prefixes and identical values."""
    limits = dict(AXIAL_LIMITS_DEG)
    for side in ("left", "right"):
        limits.update({f"{side}_{n}": lim for n, lim in ARM_LIMITS_DEG.items()})
    return limits


def restriction_problem(restrictions: tuple) -> str | None:
    """What is wrong with ``restrictions`` (one line), or None: each must name a joint once
    and narrow its range (lower < upper, both finite and within the default)."""
    defaults, seen = default_joint_limits_deg(), set()
    for item in restrictions:
        if not (isinstance(item, tuple) and len(item) == 3):
            return f"restriction {item!r} is not (joint, lower, upper)"
        name, lo, hi = item
        if name not in defaults:
            return (f"restriction joint = {name!r} is not a joint; the valid names are "
                    f"{', '.join(sorted(defaults))}")
        if name in seen:
            return f"restriction joint = {name!r} is restricted twice"
        seen.add(name)
        low, high = defaults[name]
        for value in (lo, hi):
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not (
                    math.isfinite(value) and low <= value <= high):
                return (f"{name} limit = {value!r} is outside the valid range "
                        f"{low:.0f}-{high:.0f} deg")
        if not lo < hi:
            return f"{name} limits = ({lo!r}, {hi!r}): the lower is not below the upper"
    return None


def _restricted(joint: str, lower: float | None = None, upper: float | None = None):
    """The restriction of one joint: its default range with ``lower`` or ``upper`` replaced."""
    low, high = default_joint_limits_deg()[joint]
    return ((joint, low if lower is None else lower, high if upper is None else upper),)


IMPAIRMENTS: dict[str, tuple[tuple[str, float, float], ...]] = {
    "shoulder flexion <= 90 deg": _restricted("right_shoulder_flexion", upper=90.0),
    "elbow lacks 30 deg of extension": _restricted("right_elbow_flexion", lower=30.0),
    "wrist cannot flex": _restricted("right_wrist_flexion", upper=0.0),
}
"""Each impairment's restricted joints, ``(joint, lower, upper)`` [deg]."""


def impaired(body, name: str):
    """``body`` with the impairment ``name`` (:data:`IMPAIRMENTS`)."""
    return dataclasses.replace(body, restrictions=IMPAIRMENTS[name])
