"""Each joint's load at a posture as a share of its strength: what the fatigue model is asked.

The moments are the static back-load model's (:func:`~.back.back_load`: the lumbar moment, and
the larger side's shoulder and elbow moments, the box's weight shared by the two grips). The
strengths:

- **lower back**: the twin's torso extension strength
  (:meth:`~ergohandover.twin.anthropometry.BodySpec.joint_strengths_nm`: 288 N m for the 50th-
  percentile man, Chaffin et al.; scaled by body weight × stature);
- **elbow**: isometric elbow flexion, and **shoulder**: isometric shoulder abduction, each from
  the regressions on sex, age, height and body mass of Harbo, Brincks & Andersen 2012 (Eur J
  Appl Physiol 112:267, 178 healthy people aged 15–83; their coefficients as coded in
  dambach/app_strength-Harbo). The source measured no shoulder flexion: its abduction stands in
  for the shoulder's strength (flexion, the handover's, is the stronger, so the shoulder's share
  is if anything overstated). The twin's worker has no age: :data:`AGE_YEARS` is assumed.
"""

from __future__ import annotations

import numpy as np

from ..ergonomics import Posture
from ..twin.anthropometry import BodySpec
from .back import Levers, back_load

AGE_YEARS = 40.0
"""The worker's age in the strength regressions (an assumption: the twin has no age)."""
HARBO_2012 = {
    ("male", "elbow"): (-23.8, -0.13, 22.0, 0.51),
    ("female", "elbow"): (6.9, -0.13, 9.0, 0.18),
    ("male", "shoulder"): (-30.8, -0.24, 36.0, 0.49),
    ("female", "shoulder"): (-28.2, -0.21, 35.0, 0.29),
}
"""Isometric strength [N m] = intercept + a·age [years] + h·height [m] + w·mass [kg]: elbow
flexion and shoulder abduction by sex (Harbo, Brincks & Andersen 2012)."""
JOINTS = ("shoulder", "elbow", "trunk")
"""The joints whose load a handover posture gives (the fatigue model's names)."""
SHIFT_COLUMNS = (*(f"{joint}_{kind}" for joint in JOINTS
                   for kind in ("load_share", "failure_min", "capacity_end")),
                 "shift_failure_min", "shift_capacity_end", "lifft_dose", "lifft_high_risk")
"""Every column :func:`shift_columns` gives, in order."""


def strengths_nm(body: BodySpec, age: float = AGE_YEARS) -> dict[str, float]:
    """The shoulder's, the elbow's and the lower back's (``trunk``) strength [N m]."""
    out = {}
    for joint in ("shoulder", "elbow"):
        intercept, a, h, w = HARBO_2012[(body.sex, joint)]
        out[joint] = intercept + a * age + h * body.stature_m + w * body.mass_kg
    out["trunk"] = body.joint_strengths_nm()["lumbar_flexion"]
    return out


def load_shares(posture: Posture, body: BodySpec,
                age: float = AGE_YEARS) -> dict[str, np.ndarray]:
    """Each joint's moment at each posture as a share of its strength (:data:`JOINTS`)."""
    moments = back_load(posture, Levers.of(body))
    strength = strengths_nm(body, age)
    return {"shoulder": moments["shoulder_moment_nm"] / strength["shoulder"],
            "elbow": moments["elbow_moment_nm"] / strength["elbow"],
            "trunk": np.abs(moments["back_moment_nm"]) / strength["trunk"]}


def shift_columns(posture: Posture, body: BodySpec, plan,
                  age: float = AGE_YEARS) -> dict[str, np.ndarray]:
    """A shift of handovers at each posture (``plan``: a :class:`~.fatigue.Shift`): each
    joint's load share, minutes to its first failure and capacity at the shift's end; the
    first failure of any joint (``shift_failure_min``, ``inf``: none) and the lowest capacity
    at the end (``shift_capacity_end``, NaN where a joint failed); and the low back's daily
    dose and high-risk probability (LiFFT) of the shift's handovers."""
    from .back import grip_reach_m
    from .fatigue import shift
    from .lifft import daily_dose, high_risk_probability, peak_load_moment_nm

    out: dict[str, np.ndarray] = {}
    first, lowest = None, None
    for joint, share in load_shares(posture, body, age).items():
        found = shift(share, joint, plan)
        out[f"{joint}_load_share"] = share
        out[f"{joint}_failure_min"] = found.failure_min
        out[f"{joint}_capacity_end"] = found.capacity_end
        first = found.failure_min if first is None else np.minimum(first, found.failure_min)
        lowest = found.capacity_end if lowest is None else np.fmin(lowest, found.capacity_end)
    out["shift_failure_min"] = first
    out["shift_capacity_end"] = np.where(np.isinf(first), lowest, np.nan)
    plm = peak_load_moment_nm(posture["load_kg"], grip_reach_m(posture, Levers.of(body)))
    dose = daily_dose(plm, plan.handovers)
    out["lifft_dose"] = dose
    out["lifft_high_risk"] = high_risk_probability(dose)
    return out


def shift_outcome(shares: dict[str, np.ndarray], plan, keep: float) -> dict[str, np.ndarray]:
    """Of loads ``shares`` (each joint of :data:`JOINTS` -> its load share, any shape; NaN
    where the box is not taken) over a shift (``plan``: a :class:`~.fatigue.Shift`):
    ``kept`` where every joint ends it unfailed with at least ``keep`` of its capacity, and
    ``fails`` where a joint fails during it (both False where the box is not taken)."""
    from .fatigue import capacity_at_end

    kept, fails = None, None
    for joint in JOINTS:
        share = np.asarray(shares[joint], dtype=float)
        taken = np.isfinite(share)
        left = capacity_at_end(np.where(taken, share, 0.0), joint, plan)
        good = taken & (np.nan_to_num(left, nan=-1.0) >= keep)
        bad = taken & np.isnan(left)
        kept = good if kept is None else kept & good
        fails = bad if fails is None else fails | bad
    return {"kept": kept, "fails": fails}
