"""REBA (Hignett & McAtamney 2000, Applied Ergonomics 31:201-205), vectorised over postures.

Item scores per body part and per arm, Tables A/B/C, Score A/B/C, the final score and the
action level. Both arms are scored with every adjustment; the worse arm's Table B value is the
one carried forward. What the worksheet leaves open (the upright tolerance, band-edge
inclusivity, from what angle a twist or abduction counts, single vs. each +1 for twist and
side bend) comes from :class:`~ergohandover.ergonomics.settings.ScoringSettings`.

Every returned array is (N,) int8 except ``reba_ab`` (int8 as well, 2–18).
"""

from __future__ import annotations

import numpy as np

from .bands import SCORE_DTYPE, banded, elevated, exceeds, lookup
from .posture import SIDES, Posture
from .settings import ScoringSettings

# TABLE_A[trunk 1-5][neck 1-3][legs 1-4]; six public sources agree on every cell.
TABLE_A = np.array([
    [[1, 2, 3, 4], [1, 2, 3, 4], [3, 3, 5, 6]],
    [[2, 3, 4, 5], [3, 4, 5, 6], [4, 5, 6, 7]],
    [[2, 4, 5, 6], [4, 5, 6, 7], [5, 6, 7, 8]],
    [[3, 5, 6, 7], [5, 6, 7, 8], [6, 7, 8, 9]],
    [[4, 6, 7, 8], [6, 7, 8, 9], [7, 8, 9, 9]],
], dtype=SCORE_DTYPE)
# TABLE_B[upper arm 1-6][lower arm 1-2][wrist 1-3]
TABLE_B = np.array([
    [[1, 2, 2], [1, 2, 3]],
    [[1, 2, 3], [2, 3, 4]],
    [[3, 4, 5], [4, 5, 5]],
    [[4, 5, 5], [5, 6, 7]],
    [[6, 7, 8], [7, 8, 8]],
    [[7, 8, 8], [8, 9, 9]],
], dtype=SCORE_DTYPE)
# TABLE_C[score A 1-12][score B 1-12]
TABLE_C = np.array([
    [1, 1, 1, 2, 3, 3, 4, 5, 6, 7, 7, 7],
    [1, 2, 2, 3, 4, 4, 5, 6, 6, 7, 7, 8],
    [2, 3, 3, 3, 4, 5, 6, 7, 7, 8, 8, 8],
    [3, 4, 4, 4, 5, 6, 7, 8, 8, 9, 9, 9],
    [4, 4, 4, 5, 6, 7, 8, 8, 9, 9, 9, 9],
    [6, 6, 6, 7, 8, 8, 9, 9, 10, 10, 10, 10],
    [7, 7, 7, 8, 9, 9, 9, 10, 10, 11, 11, 11],
    [8, 8, 8, 9, 10, 10, 10, 10, 10, 11, 11, 11],
    [9, 9, 9, 10, 10, 10, 11, 11, 11, 12, 12, 12],
    [10, 10, 10, 11, 11, 11, 11, 12, 12, 12, 12, 12],
    [11, 11, 11, 11, 12, 12, 12, 12, 12, 12, 12, 12],
    [12, 12, 12, 12, 12, 12, 12, 12, 12, 12, 12, 12],
], dtype=SCORE_DTYPE)

# REBA 1 negligible (0), 2-3 low (1), 4-7 medium (2), 8-10 high (3), 11-15 very high (4).
ACTION_LEVEL_EDGES = (1, 3, 7, 10)


def _twist_side_bend(twist: np.ndarray, side_bend: np.ndarray, s: ScoringSettings) -> np.ndarray:
    """The trunk/neck adjustment: +1 if twisted or side-bent (``single``), or +1 each."""
    twisted = exceeds(twist, s.twist_from_deg, s.severe_on_edge)
    bent = exceeds(side_bend, s.side_bend_from_deg, s.severe_on_edge)
    return twisted + bent if s.twist_side_bend_rule == "each" else np.maximum(twisted, bent)


def trunk(p: Posture, s: ScoringSettings) -> np.ndarray:
    """Trunk 1-5: upright 1; 0-20° flexion or extension 2; 20-60° flexion or >20° extension 3;
    >60° flexion 4; + twist/side bend. With the ``each`` rule, 6 is clipped to Table A's 5."""
    tol = s.neutral_tolerance_deg
    base = banded(p["trunk_flexion"], (-20.0, -tol, tol, 20.0, 60.0), (3, 2, 1, 2, 3, 4),
                  s.severe_on_edge)
    return np.minimum(base + _twist_side_bend(p["trunk_twist"], p["trunk_side_bend"], s), 5)


def neck(p: Posture, s: ScoringSettings) -> np.ndarray:
    """Neck 1-3: 0-20° flexion 1; >20° flexion or extension 2; + twist/side bend."""
    base = banded(p["neck_flexion"], (-s.neutral_tolerance_deg, 20.0), (2, 1, 2),
                  s.severe_on_edge)
    return np.minimum(base + _twist_side_bend(p["neck_twist"], p["neck_side_bend"], s), 3)


def legs(p: Posture, s: ScoringSettings) -> np.ndarray:
    """Legs 1-4: bilateral support or sitting 1, else 2; +1 knee flexion 30-60°, +2 beyond 60°
    (the more flexed knee), not when sitting."""
    knee = np.maximum(p["left_knee_flexion"], p["right_knee_flexion"])
    support = (2 - p["bilateral_support"]).astype(SCORE_DTYPE)
    standing = banded(knee, (30.0, 60.0), (0, 1, 2), s.severe_on_edge) + support
    return np.where(p["seated"] == 1, SCORE_DTYPE(1), standing).astype(SCORE_DTYPE)


def load(p: Posture) -> np.ndarray:
    """Load/force 0-3: <5 kg 0; 5-10 kg 1; >10 kg 2; +1 shock. The worksheet's kg bands are
    read literally (5 and 10 kg both score 1), not through the angle band-edge setting."""
    kg = p["load_kg"]
    score = (kg >= 5.0).astype(SCORE_DTYPE) + (kg > 10.0) + p["shock"].astype(SCORE_DTYPE)
    return score.astype(SCORE_DTYPE)


def upper_arm(p: Posture, side: str, s: ScoringSettings) -> np.ndarray:
    """Upper arm 1-6: 20° extension to 20° flexion 1; >20° extension or 20-45° 2; 45-90° 3;
    >90° 4; +1 abducted or rotated; +1 shoulder raised; -1 supported (minimum 1)."""
    sev = s.severe_on_edge
    score = banded(p.arm(side, "upper_arm_flexion"), (-20.0, 20.0, 45.0, 90.0), (2, 1, 2, 3, 4),
                   sev)
    score += np.maximum(exceeds(p.arm(side, "upper_arm_abduction"), s.abduction_from_deg, sev),
                        exceeds(p.arm(side, "upper_arm_rotation"), s.rotation_from_deg, sev))
    # Elevation only: the worksheets' "shoulder raised" is a shrug, not a depression.
    score += elevated(p.arm(side, "shoulder_raise"), s.shoulder_raise_from_deg, sev)
    score -= p.arm(side, "arm_supported").astype(SCORE_DTYPE)
    return np.maximum(score, 1)


def lower_arm(p: Posture, side: str, s: ScoringSettings) -> np.ndarray:
    """Lower arm 1-2: 60-100° elbow flexion 1, else 2."""
    return banded(p.arm(side, "elbow_flexion"), (60.0, 100.0), (2, 1, 2), s.severe_on_edge)


def wrist(p: Posture, side: str, s: ScoringSettings) -> np.ndarray:
    """Wrist 1-3: 0-15° flexion/extension 1, >15° 2; +1 deviated or twisted."""
    sev = s.severe_on_edge
    score = banded(np.abs(p.arm(side, "wrist_flexion")), (15.0,), (1, 2), sev)
    score += np.maximum(
        exceeds(p.arm(side, "wrist_deviation"), s.wrist_deviation_from_deg, sev),
        exceeds(p.arm(side, "wrist_twist"), s.wrist_twist_from_deg, sev),
    )
    return score


def action_level(reba_score: np.ndarray) -> np.ndarray:
    """REBA action level 0 (negligible) to 4 (very high, act now)."""
    return banded(reba_score, ACTION_LEVEL_EDGES, (0, 1, 2, 3, 4), severe_on_edge=False)


ITEM_RANGES = {
    "reba_trunk": (1, 5), "reba_neck": (1, 3), "reba_legs": (1, 4), "reba_load": (0, 3),
    **{f"reba_{side}_{item}": limits for side in SIDES for item, limits in (
        ("upper_arm", (1, 6)), ("lower_arm", (1, 2)), ("wrist", (1, 3)))},
    "reba_coupling": (0, 3), "reba_activity": (0, 3),
}
"""Each worksheet item and the scores it can take: what :func:`reba_from_items` reads."""


def items(p: Posture, s: ScoringSettings) -> dict[str, np.ndarray]:
    """The worksheet's item scores of N postures (:data:`ITEM_RANGES`' names)."""
    out = {"reba_trunk": trunk(p, s), "reba_neck": neck(p, s), "reba_legs": legs(p, s),
           "reba_load": load(p)}
    for side in SIDES:
        out[f"reba_{side}_upper_arm"] = upper_arm(p, side, s)
        out[f"reba_{side}_lower_arm"] = lower_arm(p, side, s)
        out[f"reba_{side}_wrist"] = wrist(p, side, s)
    out["reba_coupling"] = p["coupling"].astype(SCORE_DTYPE)
    out["reba_activity"] = p["activity"].astype(SCORE_DTYPE)
    return out


def reba_from_items(item: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Tables A, B and C and the final score from the worksheet's item scores.

    Args:
        item: (N,) integer arrays named as :data:`ITEM_RANGES`, each within its range.

    Returns:
        Named (N,) int8 arrays: the items (without coupling and activity), each arm's
        ``reba_{side}_table_b``, then ``reba_table_a``, ``reba_table_b`` (worse arm),
        ``reba_score_a``, ``reba_score_b``, ``reba_score_c``, ``reba``, ``reba_action_level``
        and ``reba_ab`` (Table A + Table B, the sum before Table C flattens it).
    """
    out = {name: item[name] for name in ("reba_trunk", "reba_neck", "reba_legs", "reba_load")}
    for side in SIDES:
        arm = [item[f"reba_{side}_{name}"] for name in ("upper_arm", "lower_arm", "wrist")]
        out.update(zip((f"reba_{side}_upper_arm", f"reba_{side}_lower_arm",
                        f"reba_{side}_wrist"), arm, strict=True))
        out[f"reba_{side}_table_b"] = lookup(TABLE_B, *arm)
    table_a = lookup(TABLE_A, out["reba_trunk"], out["reba_neck"], out["reba_legs"])
    table_b = np.maximum(out["reba_left_table_b"], out["reba_right_table_b"])
    score_a = table_a + out["reba_load"]
    score_b = table_b + item["reba_coupling"]
    score_c = lookup(TABLE_C, score_a, score_b)
    final = score_c + item["reba_activity"]
    out.update(
        reba_table_a=table_a,
        reba_table_b=table_b,
        reba_score_a=score_a,
        reba_score_b=score_b,
        reba_score_c=score_c,
        reba=final,
        reba_action_level=action_level(final),
        reba_ab=table_a + table_b,
    )
    return out


def reba(p: Posture, s: ScoringSettings) -> dict[str, np.ndarray]:
    """Every REBA score of N postures.

    Returns:
        Named (N,) int8 arrays: items ``reba_trunk``, ``reba_neck``, ``reba_legs``, ``reba_load``,
        per arm ``reba_{side}_upper_arm``/``_lower_arm``/``_wrist``/``_table_b``; then
        ``reba_table_a``, ``reba_table_b`` (worse arm), ``reba_score_a``, ``reba_score_b``,
        ``reba_score_c``, ``reba``, ``reba_action_level`` and ``reba_ab`` (Table A + Table B,
        the sum before Table C flattens it).
    """
    return reba_from_items(items(p, s))
