"""RULA (McAtamney & Corlett 1993, Applied Ergonomics 24:91-99), vectorised over postures.

Table A circulates in two versions that differ in 31 of 144 cells; this is the majority version
(the transcription of the 1993 paper that Ergonautas publishes). Each arm is scored on its own
(Score C per side); the grand score ``rula`` is the worse side's. Thresholds that the worksheet
leaves open come from :class:`~ergohandover.ergonomics.settings.ScoringSettings`.

Muscle use (+1, static > 1 min or repeated > 4x/min) is the ``muscle_use`` column. Force/load is
derived from ``load_kg``, ``shock`` and ``muscle_use`` (static or repeated when it is 1, else
intermittent), as McAtamney & Corlett (1993) list it: < 2 kg 0; 2-10 kg intermittent 1; 2-10 kg
static or repeated, or > 10 kg intermittent 2; > 10 kg static or repeated, or shock 3.
"""

from __future__ import annotations

import numpy as np

from .bands import SCORE_DTYPE, banded, exceeds, lookup
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
    score += exceeds(p.arm(side, "shoulder_raise"), s.shoulder_raise_from_deg, sev)
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


def force(p: Posture) -> np.ndarray:
    """Force/load 0-3 from load, shock and muscle use (kg bands read literally: 10 kg is in the
    2-10 kg band). Static or repeated (``muscle_use`` 1) adds one to the intermittent score."""
    kg = p["load_kg"]
    intermittent = np.select([kg > 10.0, kg >= 2.0], [2.0, 1.0], 0.0)
    score = np.where(kg >= 2.0, intermittent + p["muscle_use"], 0.0)
    score = np.where(p["shock"] == 1, 3.0, score)
    return score.astype(SCORE_DTYPE)


def action_level(grand: np.ndarray) -> np.ndarray:
    """RULA action level 1 (acceptable) to 4 (investigate and change now)."""
    return banded(grand, ACTION_LEVEL_EDGES, (1, 2, 3, 4), severe_on_edge=False)


def rula(p: Posture, s: ScoringSettings) -> dict[str, np.ndarray]:
    """Every RULA score of N postures.

    Returns:
        Named (N,) int8 arrays: per arm ``rula_{side}_upper_arm``/``_lower_arm``/``_wrist``/
        ``_wrist_twist``/``_table_a``/``_score_c``/``rula_{side}`` (that side's grand score);
        ``rula_neck``, ``rula_trunk``, ``rula_legs``, ``rula_force``, ``rula_table_b``,
        ``rula_score_d``; ``rula`` (the worse side) and ``rula_action_level``.
    """
    muscle = p["muscle_use"].astype(SCORE_DTYPE)
    out = {"rula_force": force(p)}
    extra = muscle + out["rula_force"]
    out["rula_neck"] = neck(p, s)
    out["rula_trunk"] = trunk(p, s)
    out["rula_legs"] = (2 - p["bilateral_support"]).astype(SCORE_DTYPE)
    out["rula_table_b"] = lookup(TABLE_B, out["rula_neck"], out["rula_trunk"], out["rula_legs"])
    out["rula_score_d"] = out["rula_table_b"] + extra
    capped_d = np.minimum(out["rula_score_d"], 7)
    for side in SIDES:
        ua, la = upper_arm(p, side, s), lower_arm(p, side, s)
        wr, tw = wrist(p, side, s), wrist_twist(p, side, s)
        table_a = lookup(TABLE_A, ua, la, wr, tw)
        score_c = table_a + extra
        out.update({
            f"rula_{side}_upper_arm": ua,
            f"rula_{side}_lower_arm": la,
            f"rula_{side}_wrist": wr,
            f"rula_{side}_wrist_twist": tw,
            f"rula_{side}_table_a": table_a,
            f"rula_{side}_score_c": score_c,
            f"rula_{side}": lookup(TABLE_C, np.minimum(score_c, 8), capped_d),
        })
    out["rula"] = np.maximum(out["rula_left"], out["rula_right"])
    out["rula_action_level"] = action_level(out["rula"])
    return out
