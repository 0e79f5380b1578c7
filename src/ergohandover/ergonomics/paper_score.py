"""The paper's own "postural score": the additive score its published calculator computes.

This is the score Amani & Akhavian optimise. It is *not* table-based REBA: it adds item scores
without Tables A/B/C and has no wrist, load, coupling or activity terms. It is reproduced here
with its quirks, as the paper's own rule (``../shared/reference/paper_code_facts.md``):

- neck 2 if any neck angle's magnitude exceeds 20°, else 1 (REBA: extension scores 2);
- trunk 1 if |flexion| <= 3°, 2 if extended beyond 3°, 3 if flexed beyond 3°; +1 if twist
  exceeds 2° (side bend is not counted; REBA grades flexion at 20° and 60°);
- legs 1, +1 if the knee is flexed above 2° and below 60°, +2 above 60° (exactly 60° adds
  nothing);
- +1 if either hand is higher than the neck;
- per arm: upper arm 1 within ±20°, 2 flexed beyond 20°, **0** extended beyond 20° (REBA: 2;
  45° and 90° are not graded); lower arm 1 for 60–100° elbow flexion, 2 above 100°, **0** below
  60° (REBA: 2); the larger arm total is added.

The thresholds are the code's fixed numbers; :class:`ScoringSettings` does not apply. Where the
code's text leaves a detail open, the choice made here: the knee term uses the more flexed knee,
and the 60–100° elbow band and the ±20° upper-arm band include their ends.
With the box in front of the body the practical minimum is 4.
"""

from __future__ import annotations

import numpy as np

from .bands import SCORE_DTYPE
from .posture import SIDES, Posture


def _i8(mask: np.ndarray) -> np.ndarray:
    return mask.astype(SCORE_DTYPE)


def arm(p: Posture, side: str) -> np.ndarray:
    """One arm's upper-arm + lower-arm total, 0-4."""
    flexion = p.arm(side, "upper_arm_flexion")
    elbow = p.arm(side, "elbow_flexion")
    upper = _i8(np.abs(flexion) <= 20.0) + 2 * _i8(flexion > 20.0)
    lower = _i8((elbow >= 60.0) & (elbow <= 100.0)) + 2 * _i8(elbow > 100.0)
    return upper + lower


def items(p: Posture) -> dict[str, np.ndarray]:
    """The paper's item scores of N postures: ``paper_neck``, ``paper_trunk``, ``paper_legs``,
    ``paper_hands_above_neck``, ``paper_left_arm`` and ``paper_right_arm``."""
    neck_mag = np.maximum(np.maximum(np.abs(p["neck_flexion"]), np.abs(p["neck_side_bend"])),
                          np.abs(p["neck_twist"]))
    trunk_flexion = p["trunk_flexion"]
    knee = np.maximum(p["left_knee_flexion"], p["right_knee_flexion"])
    out = {
        "paper_neck": 1 + _i8(neck_mag > 20.0),
        "paper_trunk": (1 + _i8(trunk_flexion < -3.0) + 2 * _i8(trunk_flexion > 3.0)
                        + _i8(np.abs(p["trunk_twist"]) > 2.0)),
        "paper_legs": 1 + _i8((knee > 2.0) & (knee < 60.0)) + 2 * _i8(knee > 60.0),
        "paper_hands_above_neck": _i8(p["hands_above_neck"] == 1),
    }
    for side in SIDES:
        out[f"paper_{side}_arm"] = arm(p, side)
    return out


def paper_from_items(item: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The items and their total ``paper_postural`` (neck + trunk + legs + hands + the larger
    arm)."""
    return {**item, "paper_postural": (
        item["paper_neck"] + item["paper_trunk"] + item["paper_legs"]
        + item["paper_hands_above_neck"]
        + np.maximum(item["paper_left_arm"], item["paper_right_arm"]))}


def paper_postural(p: Posture) -> dict[str, np.ndarray]:
    """The paper's postural score of N postures.

    Returns:
        Named (N,) int8 arrays: ``paper_neck``, ``paper_trunk``, ``paper_legs``,
        ``paper_hands_above_neck``, ``paper_left_arm``, ``paper_right_arm`` and their total
        ``paper_postural`` (neck + trunk + legs + hands + the larger arm).
    """
    return paper_from_items(items(p))
