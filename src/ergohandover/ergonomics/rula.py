"""RULA (McAtamney & Corlett 1993, Applied Ergonomics 24:91-99), vectorised over postures.

Table A circulates in two versions that differ in 31 of 144 cells; this is the majority version
(the transcription of the 1993 paper that Ergonautas publishes). Each arm is scored on its own
(Score C per side); the grand score ``rula`` is the worse side's. Thresholds that the worksheet
leaves open come from :class:`~ergohandover.ergonomics.settings.ScoringSettings`.

Muscle use (+1, static > 1 min or repeated > 4x/min) and force/load are given per group, as the
worksheet scores them: the arm-and-wrist group's from ``muscle_use`` and ``load_kg``, the
neck-trunk-leg group's from ``neck_trunk_legs_muscle_use`` and ``neck_trunk_legs_load_kg`` (the
arm group's when absent). Force/load is derived from the load, ``shock`` and the group's muscle
use (static or repeated when it is 1, else intermittent), as McAtamney & Corlett (1993) list it:
< 2 kg 0; 2-10 kg intermittent 1; 2-10 kg static or repeated, or > 10 kg intermittent 2; > 10 kg
static or repeated, or shock 3.
"""

from __future__ import annotations

import numpy as np

from .bands import SCORE_DTYPE, banded, elevated, exceeds, lookup
from .posture import SIDES, Posture
from .settings import ScoringSettings

# TABLE_A[upper arm 1-6][lower arm 1-3][(wrist 1-4 - 1) * 2 + (wrist twist 1-2 - 1)]
TABLE_A = np.array([
    [[1, 2, 2, 2, 2, 3, 3, 3], [2, 2, 2, 2, 3, 3, 3, 3], [2, 3, 3, 3, 3, 3, 4, 4]],
    [[2, 3, 3, 3, 3, 4, 4, 4], [3, 3, 3, 3, 3, 4, 4, 4], [3, 4, 4, 4, 4, 4, 5, 5]],
    [[3, 3, 4, 4, 4, 4, 5, 5], [3, 4, 4, 4, 4, 4, 5, 5], [4, 4, 4, 4, 4, 5, 5, 5]],
    [[4, 4, 4, 4, 4, 5, 5, 5], [4, 4, 4, 4, 4, 5, 5, 5], [4, 4, 4, 5, 5, 5, 6, 6]],
    [[5, 5, 5, 5, 5, 6, 6, 7], [5, 6, 6, 6, 6, 7, 7, 7], [6, 6, 6, 7, 7, 7, 7, 8]],
    [[7, 7, 7, 7, 7, 8, 8, 9], [8, 8, 8, 8, 8, 9, 9, 9], [9, 9, 9, 9, 9, 9, 9, 9]],
], dtype=SCORE_DTYPE).reshape(6, 3, 4, 2)
# TABLE_B[neck 1-6][trunk 1-6][legs 1-2]
TABLE_B = np.array([
    [[1, 3], [2, 3], [3, 4], [5, 5], [6, 6], [7, 7]],
    [[2, 3], [2, 3], [4, 5], [5, 5], [6, 7], [7, 7]],
    [[3, 3], [3, 4], [4, 5], [5, 6], [6, 7], [7, 7]],
    [[5, 5], [5, 6], [6, 7], [7, 7], [7, 7], [8, 8]],
    [[7, 7], [7, 7], [7, 8], [8, 8], [8, 8], [8, 8]],
    [[8, 8], [8, 8], [8, 8], [8, 9], [9, 9], [9, 9]],
], dtype=SCORE_DTYPE)
# TABLE_C[min(score C, 8)][min(score D, 7)]
TABLE_C = np.array([
    [1, 2, 3, 3, 4, 5, 5],
    [2, 2, 3, 4, 4, 5, 5],
    [3, 3, 3, 4, 4, 5, 6],
    [3, 3, 3, 4, 5, 6, 6],
    [4, 4, 4, 5, 6, 7, 7],
    [4, 4, 5, 6, 6, 7, 7],
    [5, 5, 6, 6, 7, 7, 7],
    [5, 5, 6, 7, 7, 7, 7],
], dtype=SCORE_DTYPE)

# RULA 1-2 acceptable (1), 3-4 investigate (2), 5-6 investigate and change soon (3), 7 now (4).
ACTION_LEVEL_EDGES = (2, 4, 6)


def upper_arm(p: Posture, side: str, s: ScoringSettings) -> np.ndarray:
    """Upper arm 1-6: 20° extension to 20° flexion 1; >20° extension or 20-45° 2; 45-90° 3;
    >90° 4; +1 shoulder raised; +1 abducted; -1 supported (minimum 1)."""
    sev = s.severe_on_edge
    score = banded(p.arm(side, "upper_arm_flexion"), (-20.0, 20.0, 45.0, 90.0), (2, 1, 2, 3, 4),
                   sev)
    # Elevation only: the worksheets' "shoulder raised" is a shrug, not a depression.
    score += elevated(p.arm(side, "shoulder_raise"), s.shoulder_raise_from_deg, sev)
    score += exceeds(p.arm(side, "upper_arm_abduction"), s.abduction_from_deg, sev)
    score -= p.arm(side, "arm_supported").astype(SCORE_DTYPE)
    return np.maximum(score, 1)


def lower_arm(p: Posture, side: str, s: ScoringSettings) -> np.ndarray:
    """Lower arm 1-3: 60-100° 1, else 2; +1 working across the midline or out to the side."""
    score = banded(p.arm(side, "elbow_flexion"), (60.0, 100.0), (2, 1, 2), s.severe_on_edge)
    return score + p.arm(side, "arm_across_midline").astype(SCORE_DTYPE)


def wrist(p: Posture, side: str, s: ScoringSettings) -> np.ndarray:
    """Wrist 1-4: neutral 1; 0-15° flexion/extension 2; >15° 3; +1 deviated."""
    sev = s.severe_on_edge
    score = banded(np.abs(p.arm(side, "wrist_flexion")), (s.neutral_tolerance_deg, 15.0),
                   (1, 2, 3), sev)
    return score + exceeds(p.arm(side, "wrist_deviation"), s.wrist_deviation_from_deg, sev)


def wrist_twist(p: Posture, side: str, s: ScoringSettings) -> np.ndarray:
    """Wrist twist 1-2: mid-range 1; near the end of its range 2."""
    return 1 + exceeds(p.arm(side, "wrist_twist"), s.wrist_twist_from_deg, s.severe_on_edge)


def _twisted_and_bent(twist: np.ndarray, side_bend: np.ndarray, s: ScoringSettings):
    return (exceeds(twist, s.twist_from_deg, s.severe_on_edge)
            + exceeds(side_bend, s.side_bend_from_deg, s.severe_on_edge))


def neck(p: Posture, s: ScoringSettings) -> np.ndarray:
    """Neck 1-6: 0-10° flexion 1; 10-20° 2; >20° 3; extension 4; +1 twisted; +1 side-bent."""
    base = banded(p["neck_flexion"], (-s.neutral_tolerance_deg, 10.0, 20.0), (4, 1, 2, 3),
                  s.severe_on_edge)
    return base + _twisted_and_bent(p["neck_twist"], p["neck_side_bend"], s)


def trunk(p: Posture, s: ScoringSettings) -> np.ndarray:
    """Trunk 1-6: upright 1; 0-20° flexion 2; 20-60° 3; >60° 4; +1 twisted; +1 side-bent.
    RULA gives no band for extension: beyond the neutral tolerance it scores 2."""
    tol = s.neutral_tolerance_deg
    base = banded(p["trunk_flexion"], (-tol, tol, 20.0, 60.0), (2, 1, 2, 3, 4), s.severe_on_edge)
    return base + _twisted_and_bent(p["trunk_twist"], p["trunk_side_bend"], s)


def force(kg: np.ndarray, muscle_use: np.ndarray, shock: np.ndarray) -> np.ndarray:
    """Force/load 0-3 of one group from its load [kg], muscle use and shock (kg bands read
    literally: 10 kg is in the 2-10 kg band). Static or repeated (muscle use 1) adds one to the
    intermittent score."""
    intermittent = np.select([kg > 10.0, kg >= 2.0], [2.0, 1.0], 0.0)
    score = np.where(kg >= 2.0, intermittent + muscle_use, 0.0)
    score = np.where(shock == 1, 3.0, score)
    return score.astype(SCORE_DTYPE)


def action_level(grand: np.ndarray) -> np.ndarray:
    """RULA action level 1 (acceptable) to 4 (investigate and change now)."""
    return banded(grand, ACTION_LEVEL_EDGES, (1, 2, 3, 4), severe_on_edge=False)


ITEM_RANGES = {
    **{f"rula_{side}_{item}": limits for side in SIDES for item, limits in (
        ("upper_arm", (1, 6)), ("lower_arm", (1, 3)), ("wrist", (1, 4)),
        ("wrist_twist", (1, 2)))},
    "rula_arm_muscle_use": (0, 1), "rula_arm_force": (0, 3),
    "rula_neck": (1, 6), "rula_trunk": (1, 6), "rula_legs": (1, 2),
    "rula_neck_trunk_legs_muscle_use": (0, 1), "rula_neck_trunk_legs_force": (0, 3),
}
"""Each worksheet item and the scores it can take: what :func:`rula_from_items` reads
(``rula_arm_force`` and ``rula_arm_muscle_use`` are the arm-and-wrist group's)."""


def items(p: Posture, s: ScoringSettings) -> dict[str, np.ndarray]:
    """The worksheet's item scores of N postures (:data:`ITEM_RANGES`' names)."""
    out = {}
    for side in SIDES:
        out[f"rula_{side}_upper_arm"] = upper_arm(p, side, s)
        out[f"rula_{side}_lower_arm"] = lower_arm(p, side, s)
        out[f"rula_{side}_wrist"] = wrist(p, side, s)
        out[f"rula_{side}_wrist_twist"] = wrist_twist(p, side, s)
    body_muscle = p["neck_trunk_legs_muscle_use"]
    out.update(
        rula_arm_muscle_use=p["muscle_use"].astype(SCORE_DTYPE),
        rula_arm_force=force(p["load_kg"], p["muscle_use"], p["shock"]),
        rula_neck=neck(p, s), rula_trunk=trunk(p, s),
        rula_legs=(2 - p["bilateral_support"]).astype(SCORE_DTYPE),
        rula_neck_trunk_legs_muscle_use=body_muscle.astype(SCORE_DTYPE),
        rula_neck_trunk_legs_force=force(p["neck_trunk_legs_load_kg"], body_muscle, p["shock"]),
    )
    return out


def rula_from_items(item: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Tables A, B and C and the grand score from the worksheet's item scores.

    Args:
        item: (N,) integer arrays named as :data:`ITEM_RANGES`, each within its range.

    Returns:
        Named (N,) int8 arrays: ``rula_arm_force``, ``rula_neck_trunk_legs_force``, ``rula_neck``,
        ``rula_trunk``, ``rula_legs``, ``rula_table_b``, ``rula_score_d``; per arm
        ``rula_{side}_upper_arm``/``_lower_arm``/``_wrist``/``_wrist_twist``/``_table_a``/
        ``_score_c``/``rula_{side}`` (that side's grand score); ``rula`` (the worse side) and
        ``rula_action_level``.
    """
    arm_extra = item["rula_arm_muscle_use"] + item["rula_arm_force"]
    body_extra = item["rula_neck_trunk_legs_muscle_use"] + item["rula_neck_trunk_legs_force"]
    out = {"rula_arm_force": item["rula_arm_force"],
           "rula_neck_trunk_legs_force": item["rula_neck_trunk_legs_force"]}
    for name in ("rula_neck", "rula_trunk", "rula_legs"):
        out[name] = item[name]
    out["rula_table_b"] = lookup(TABLE_B, out["rula_neck"], out["rula_trunk"], out["rula_legs"])
    out["rula_score_d"] = out["rula_table_b"] + body_extra
    capped_d = np.minimum(out["rula_score_d"], 7)
    for side in SIDES:
        arm = [item[f"rula_{side}_{name}"]
               for name in ("upper_arm", "lower_arm", "wrist", "wrist_twist")]
        table_a = lookup(TABLE_A, *arm)
        score_c = table_a + arm_extra
        out.update(zip((f"rula_{side}_upper_arm", f"rula_{side}_lower_arm", f"rula_{side}_wrist",
                        f"rula_{side}_wrist_twist"), arm, strict=True))
        out.update({
            f"rula_{side}_table_a": table_a,
            f"rula_{side}_score_c": score_c,
            f"rula_{side}": lookup(TABLE_C, np.minimum(score_c, 8), capped_d),
        })
    out["rula"] = np.maximum(out["rula_left"], out["rula_right"])
    out["rula_action_level"] = action_level(out["rula"])
    return out


def rula(p: Posture, s: ScoringSettings) -> dict[str, np.ndarray]:
    """Every RULA score of N postures (:func:`rula_from_items` of the postures' items)."""
    return rula_from_items(items(p, s))
