"""An independent, one-posture-at-a-time transcription of the worksheets, for cross-checks.

Written as an observer would read the worksheets (if/elif on each band), against the
vectorised cumulative-band implementation in the package. Tables are parsed from the text of
``reba_rula_tables.md`` embedded in ``tables_text.py``.
"""

from __future__ import annotations

from tables_text import parse_tables

T = parse_tables()


def _within(settings):
    """within(x, limit): x is still inside the less severe band whose end is ``limit``."""
    if settings.band_edge == "lower":
        return lambda x, limit: x <= limit
    return lambda x, limit: x < limit


def _get(table, *one_based):
    for i in one_based:
        table = table[i - 1]
    return table


def reba(p: dict, s) -> dict:
    within = _within(s)

    def exceeds(x, limit):
        return not within(abs(x), limit)

    def adjust(twist, bend):
        t, b = exceeds(twist, s.twist_from_deg), exceeds(bend, s.side_bend_from_deg)
        return t + b if s.twist_side_bend_rule == "each" else int(t or b)

    f = p["trunk_flexion"]
    if within(abs(f), s.neutral_tolerance_deg):
        trunk = 1
    elif within(abs(f), 20):
        trunk = 2
    elif f < 0 or within(f, 60):
        trunk = 3
    else:
        trunk = 4
    trunk = min(trunk + adjust(p["trunk_twist"], p["trunk_side_bend"]), 5)

    n = p["neck_flexion"]
    # -n is how far the neck is extended; beyond the tolerance is extension.
    neck = 2 if not within(-n, s.neutral_tolerance_deg) or not within(n, 20) else 1
    neck = min(neck + adjust(p["neck_twist"], p["neck_side_bend"]), 3)

    knee = max(p["left_knee_flexion"], p["right_knee_flexion"])
    legs = (1 if p["bilateral_support"] == 1 else 2) + (
        0 if within(knee, 30) else 1 if within(knee, 60) else 2)
    if p["seated"] == 1:  # sitting: 1, the knee adjustment is not for sitting
        legs = 1

    kg = p["load_kg"]
    load = (0 if kg < 5 else 1 if kg <= 10 else 2) + int(p["shock"] == 1)

    out = {"reba_trunk": trunk, "reba_neck": neck, "reba_legs": legs, "reba_load": load}
    for side in ("left", "right"):
        a = {k[len(side) + 1:]: v for k, v in p.items() if k.startswith(side + "_")}
        u = a["upper_arm_flexion"]
        if within(abs(u), 20):
            ua = 1
        elif u < 0 or within(u, 45):
            ua = 2
        elif within(u, 90):
            ua = 3
        else:
            ua = 4
        ua += int(exceeds(a["upper_arm_abduction"], s.abduction_from_deg)
                  or exceeds(a["upper_arm_rotation"], s.rotation_from_deg))
        # Raised means elevated: a depressed shoulder (negative) never counts.
        ua += int(not within(a["shoulder_raise"], s.shoulder_raise_from_deg))
        ua = max(ua - int(a["arm_supported"] == 1), 1)
        e = a["elbow_flexion"]
        la = 1 if within(60 - e, 0) and within(e - 100, 0) else 2
        wr = (1 if within(abs(a["wrist_flexion"]), 15) else 2) + int(
            exceeds(a["wrist_deviation"], s.wrist_deviation_from_deg)
            or exceeds(a["wrist_twist"], s.wrist_twist_from_deg))
        out.update({f"reba_{side}_upper_arm": ua, f"reba_{side}_lower_arm": la,
                    f"reba_{side}_wrist": wr,
                    f"reba_{side}_table_b": _get(T["reba_b"], ua, la, wr)})
    table_a = _get(T["reba_a"], trunk, neck, legs)
    table_b = max(out["reba_left_table_b"], out["reba_right_table_b"])
    score_a, score_b = table_a + load, table_b + int(p["coupling"])
    score_c = _get(T["reba_c"], score_a, score_b)
    final = score_c + int(p["activity"])
    level = 0 if final == 1 else 1 if final <= 3 else 2 if final <= 7 else 3 if final <= 10 else 4
    out.update(reba_table_a=table_a, reba_table_b=table_b, reba_score_a=score_a,
               reba_score_b=score_b, reba_score_c=score_c, reba=final,
               reba_action_level=level, reba_ab=table_a + table_b)
    return out


def rula(p: dict, s) -> dict:
    within = _within(s)
    tol = s.neutral_tolerance_deg

    def exceeds(x, limit):
        return int(not within(abs(x), limit))

    def force_of(kg, muscle_use):
        if p["shock"] == 1:
            return 3
        if kg > 10:
            return 2 + int(muscle_use)
        if kg >= 2:
            return 1 + int(muscle_use)
        return 0

    force = force_of(p["load_kg"], p["muscle_use"])
    extra = int(p["muscle_use"]) + force
    body_muscle = p.get("neck_trunk_legs_muscle_use", p["muscle_use"])
    body_force = force_of(p.get("neck_trunk_legs_load_kg", p["load_kg"]), body_muscle)
    body_extra = int(body_muscle) + body_force
    n = p["neck_flexion"]
    neck = 4 if not within(-n, tol) else 1 if within(n, 10) else 2 if within(n, 20) else 3
    neck += exceeds(p["neck_twist"], s.twist_from_deg)
    neck += exceeds(p["neck_side_bend"], s.side_bend_from_deg)
    f = p["trunk_flexion"]
    if within(abs(f), tol):
        trunk = 1
    elif f < 0 or within(f, 20):
        trunk = 2
    else:
        trunk = 3 if within(f, 60) else 4
    trunk += exceeds(p["trunk_twist"], s.twist_from_deg)
    trunk += exceeds(p["trunk_side_bend"], s.side_bend_from_deg)
    legs = 1 if p["bilateral_support"] == 1 else 2
    table_b = _get(T["rula_b"], neck, trunk, legs)
    out = {"rula_arm_force": force, "rula_neck_trunk_legs_force": body_force, "rula_neck": neck,
           "rula_trunk": trunk, "rula_legs": legs, "rula_table_b": table_b,
           "rula_score_d": table_b + body_extra}
    for side in ("left", "right"):
        a = {k[len(side) + 1:]: v for k, v in p.items() if k.startswith(side + "_")}
        u = a["upper_arm_flexion"]
        if within(abs(u), 20):
            ua = 1
        elif u < 0 or within(u, 45):
            ua = 2
        else:
            ua = 3 if within(u, 90) else 4
        ua += int(not within(a["shoulder_raise"], s.shoulder_raise_from_deg))  # elevation only
        ua += exceeds(a["upper_arm_abduction"], s.abduction_from_deg)
        ua = max(ua - int(a["arm_supported"] == 1), 1)
        e = a["elbow_flexion"]
        la = (1 if within(60 - e, 0) and within(e - 100, 0) else 2) + int(
            a["arm_across_midline"] == 1)
        w = abs(a["wrist_flexion"])
        wr = (1 if within(w, tol) else 2 if within(w, 15) else 3) + exceeds(
            a["wrist_deviation"], s.wrist_deviation_from_deg)
        tw = 1 + exceeds(a["wrist_twist"], s.wrist_twist_from_deg)
        table_a = T["rula_a"][ua - 1][la - 1][(wr - 1) * 2 + (tw - 1)]
        score_c = table_a + extra
        grand = _get(T["rula_c"], min(score_c, 8), min(table_b + body_extra, 7))
        out.update({f"rula_{side}_upper_arm": ua, f"rula_{side}_lower_arm": la,
                    f"rula_{side}_wrist": wr, f"rula_{side}_wrist_twist": tw,
                    f"rula_{side}_table_a": table_a, f"rula_{side}_score_c": score_c,
                    f"rula_{side}": grand})
    out["rula"] = max(out["rula_left"], out["rula_right"])
    r = out["rula"]
    out["rula_action_level"] = 1 if r <= 2 else 2 if r <= 4 else 3 if r <= 6 else 4
    return out
