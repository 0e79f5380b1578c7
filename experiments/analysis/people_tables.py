"""The people part's blocks, from results/people/ only: the report's paragraph behind the
README's headline row "beside people", and its tables of where people received, how well each
predictor (the twin among them) predicts their posture against the constant, where the twin
predicts they receive, how far they received from its recommendation, and what the fit of its
weights did.
``python people_tables.py`` rewrites them after the study."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
from readme_blocks import rewrite

ANGLE_NAMES = {"trunk_flexion": "trunk flexion", "neck_flexion": "neck flexion",
               "knee_flexion": "knee flexion (receiving side)",
               "upper_arm_flexion": "upper-arm flexion (receiving arm)",
               "upper_arm_abduction": "upper-arm abduction (receiving arm)",
               "elbow_flexion": "elbow flexion (receiving arm)"}
SCORE_NAMES = {"reba": "REBA", "rula": "RULA", "paper_postural": "paper"}
CAVEAT = ("Kim et al. (ICRA 2025): dynamic handovers, mostly one-handed, of small objects "
          "named nowhere, by receivers the data do not tell apart, tracked by a ZED2i camera's "
          "fixed-proportion skeleton.")


PREDICTOR_NAMES = {"constant": "constant (training mean)",
                   "line": "straight line (hand place, stature)",
                   "neighbours": "10 nearest neighbours",
                   "twin": "twin", "fitted twin": "fitted twin",
                   "line + twin": "line + twin"}
ALL = "all six"


def _read(results: Path) -> dict:
    folder = results / "people"
    return {"skill": pd.read_csv(folder / "skill.csv"),
            "locations": pd.read_csv(folder / "locations.csv"),
            "advice": pd.read_csv(folder / "recommendation.csv"),
            "receiving": pd.read_csv(folder / "receiving.csv"),
            "ranking": pd.read_csv(folder / "ranking.csv"),
            "study": pd.read_csv(folder / "study_task.csv"),
            "manifest": json.loads((folder / "manifest.json").read_text())}


def _skill(row) -> str:
    return f"{row.skill:+.2f} ({row.skill_low:+.2f} to {row.skill_high:+.2f})"


def pooled(results: Path, group: str = "held-out") -> pd.DataFrame:
    """Per predictor, its row pooling every angle (:data:`ALL`) in ``group``."""
    skill = _read(results)["skill"]
    return skill[(skill["group"] == group) & (skill["angle"] == ALL)].set_index("predictor")


def headline(results: Path) -> str:
    """The report's paragraph: N, skill against the constant and the line, held out and out of
    distribution, what the twin alone does, where people received and the ranking."""
    data = _read(results)
    manifest = data["manifest"]
    held, out = pooled(results), pooled(results, "out-of-distribution")
    skill = data["skill"].query("group == 'held-out' and predictor == 'line + twin' "
                                "and angle != @ALL").set_index("angle")
    unsure = [ANGLE_NAMES[a].split(" (")[0] for a in skill.index if skill.loc[a, "skill_low"] <= 0]
    where = data["receiving"].query("group == 'held-out'").set_index("score").loc["paper_postural"]
    ranking = data["ranking"].query("group == 'held-out'").set_index("score")
    reba = data["advice"].set_index("score").loc["reba"]
    total = manifest["handovers"] + sum(manifest["dropped"].values())
    n = int(held.loc["constant", "n"]) // len(ANGLE_NAMES)
    return (f"{manifest['handovers']:,} of {total:,} measured handovers (Kim et al. 2025: "
            f"dynamic, one-handed, small objects, ZED keypoints), both sides' angles read through "
            f"the same keypoints; held out ({n} handovers), the line + twin predicts the six joint "
            f"angles with skill {_skill(held.loc['line + twin'])} against the training mean "
            f"(RMSE {held.loc['line + twin', 'rmse_deg']:.1f}° against "
            f"{held.loc['constant', 'rmse_deg']:.1f}°), above the straight line in the hand's "
            f"place and stature ({held.loc['line', 'rmse_deg']:.1f}°, skill "
            f"{held.loc['line', 'skill']:+.2f}), below 10 nearest neighbours "
            f"({held.loc['neighbours', 'rmse_deg']:.1f}°); the noise ceiling is "
            f"{held.loc['constant', 'ceiling_rmse_deg']:.1f}°"
            + (f"; its interval includes no skill for {', '.join(unsure)}" if unsure else "")
            + f"; out of distribution its skill is {_skill(out.loc['line + twin'])}. The twin "
            f"alone scores {held.loc['twin', 'skill']:+.2f} (RMSE "
            f"{held.loc['twin', 'rmse_deg']:.1f}°), fitted {held.loc['fitted twin', 'skill']:+.2f}."
            f" Without the person's hand, the twin's paper-score optimum places it "
            f"{where['twin_rmse_cm']:.0f} cm (RMSE) from where people took the object, the "
            f"training mean {where['mean_rmse_cm']:.0f} cm (skill {_skill(where)}); "
            f"{100 * reba['within_step_share']:.0f} % of hands lie within one grid step of the "
            f"twin's REBA optimum, {100 * reba['within_step_null_share']:.0f} % after moving every "
            f"hand 10 cm at random. The twin's scores where people received rank people's "
            f"measured scores with Spearman {ranking.loc['reba', 'spearman']:.2f} "
            f"({ranking.loc['reba', 'low']:.2f} to {ranking.loc['reba', 'high']:.2f}) on REBA, "
            f"{ranking.loc['rula', 'spearman']:.2f} on RULA, "
            f"{ranking.loc['paper_postural', 'spearman']:.2f} on the paper score; "
            f"{fit_clause(data)}")


def _span(row) -> str:
    lo, hi = row["people_lo_median"], row["people_hi_median"]
    return f"{lo:g}" if lo == hi else f"{lo:g}–{hi:g}"


def at_bounds(factors: dict[str, float]) -> list[str]:
    """The fitted factors at the search's bounds (0.1 or 10): the data do not pin them."""
    return [name for name, value in factors.items() if value <= 0.101 or value >= 9.9]


def fit_clause(data: dict) -> str:
    """Whether the fitted weights are the default, and why, from the part's results."""
    manifest = data["manifest"]
    rmse, within = manifest["angle_rmse_deg"], manifest["published_conditions_within"]
    bounded = at_bounds(manifest["fit_factors"])
    total = len(data["study"]) // 2
    return (f"fitted weights cut the twin's held-out angle RMSE from "
            f"{rmse['default']['held-out']:.1f}° to {rmse['fitted']['held-out']:.1f}° but are not "
            f"the default: "
            + (f"{', '.join(n.replace('_', ' ') for n in bounded)} "
               f"{'sits' if len(bounded) == 1 else 'sit'} at the search's bound, "
               if bounded else "")
            + f"they come from another task, and on the study's own they meet "
            f"{within['fitted']} of {total} published conditions (the default {within['default']})")


def locations_table(results: Path) -> list[str]:
    data = _read(results)
    lines = ["| where the object was taken | N | median | quartiles | 5th–95th percentile |",
             "|---|---|---|---|---|"]
    for row in data["locations"].itertuples():
        lines.append(f"| {row.quantity} | {row.n:,} | {row.median:.3f} | {row.p25:.3f} to "
                     f"{row.p75:.3f} | {row.p5:.3f} to {row.p95:.3f} |")
    return lines


def calibration_text(results: Path) -> str:
    """What the standing frames hold, and each side's calibrated angles at the transfer."""
    table = pd.read_csv(results / "people" / "handovers.csv")
    angles = ("trunk_flexion", "neck_flexion", "knee_flexion")

    def medians(prefix: str) -> str:
        return ", ".join(f"{ANGLE_NAMES[a].split(' (')[0].split(' ')[0]} "
                         f"{table[prefix + a].median():+.1f}°" for a in angles)

    return (f"Standing (both knees within 10° of straight), the tracker reads the receivers at a "
            f"median of {medians('neutral_')}: the zero of its skeleton rather than a posture "
            f"(the trunk reads leaning back in "
            f"{100 * (table['neutral_trunk_flexion'] < 0).mean():.0f} % of the recordings). "
            f"Each recording's trunk, neck and knee flexion are read from its own standing "
            f"median, the twin's from its upright posture through the same keypoints. So read, "
            f"at the transfer the receivers hold {medians('measured_')} (medians), the twin "
            f"{medians('twin_')}")


def skill_table(results: Path) -> list[str]:
    """Per angle (and all six) and predictor, held out and out of distribution: RMSE and skill
    against the constant with its interval; the noise ceiling in the last row."""
    skill = _read(results)["skill"].set_index(["group", "predictor", "angle"])
    lines = []
    for group in ("held-out", "out-of-distribution"):
        n = int(skill.loc[(group, "constant", "trunk_flexion"), "n"])
        lines += [f"| {group} (N = {n}) | " + " | ".join(
            PREDICTOR_NAMES[p] for p in PREDICTOR_NAMES) + " | noise ceiling |",
            "|---|" + "---|" * (len(PREDICTOR_NAMES) + 1)]
        for angle, name in (*ANGLE_NAMES.items(), (ALL, "all six angles")):
            cells = [f"{skill.loc[(group, p, angle), 'rmse_deg']:.1f}° "
                     f"[{_skill(skill.loc[(group, p, angle)])}]" if p != "constant"
                     else f"{skill.loc[(group, p, angle), 'rmse_deg']:.1f}°"
                     for p in PREDICTOR_NAMES]
            ceiling = skill.loc[(group, "constant", angle), "ceiling_rmse_deg"]
            lines.append(f"| {name} | " + " | ".join(cells) + f" | {ceiling:.1f}° |")
        lines.append("")
    return [*lines, "Each cell: RMSE [skill against the constant, 1 − MSE/MSE(constant) (its "
            "95 % bootstrap interval over handovers)]. Noise ceiling: the root mean square "
            "of each angle's spread over the frames within 0.1 s of the transfer."]


def receiving_table(results: Path) -> list[str]:
    """Per score: the twin's optimum as the predicted receiving point, against the training
    mean, held out and out of distribution; and the rank correlation of the scores."""
    data = _read(results)
    ranking = data["ranking"].set_index(["score", "group"])
    lines = ["| score | group (N) | the twin's optimum: RMSE (median) [cm] | training mean: "
             "RMSE (median) [cm] | skill | Spearman, twin's score against people's |",
             "|---|---|---|---|---|---|"]
    for row in data["receiving"].itertuples():
        rank = ranking.loc[(row.score, row.group)]
        lines.append(f"| {SCORE_NAMES[row.score]} | {row.group} ({row.n}) | "
                     f"{row.twin_rmse_cm:.0f} ({row.twin_median_cm:.0f}) | {row.mean_rmse_cm:.0f}"
                     f" ({row.mean_median_cm:.0f}) | {_skill(row)} | {rank.spearman:.2f} "
                     f"({rank.low:.2f} to {rank.high:.2f}) |")
    return lines


def recommendation_table(results: Path) -> list[str]:
    data = _read(results)
    lines = ["| score | the twin's optimum (x, y, z) [m] (cells at it) | people's hands from the "
             "nearest optimal cell: median (quartiles) [cm] | within one grid step (hands "
             "moved 10 cm at random) | the twin where people received: median (at its "
             "optimum) | people's measured score: median interval (holds the optimum) |",
             "|---|---|---|---|---|---|"]
    for row in data["advice"].itertuples():
        lines.append(
            f"| {SCORE_NAMES[row.score]} | {row.optimum} at ({row.optimum_x:.2f}, "
            f"{row.optimum_y:.2f}, {row.optimum_z:.2f}) ({row.optimum_cells:,}) | "
            f"{100 * row.distance_median_m:.0f} ({100 * row.distance_p25_m:.0f}–"
            f"{100 * row.distance_p75_m:.0f}) | {100 * row.within_step_share:.0f} % "
            f"({100 * row.within_step_null_share:.0f} %) | "
            f"{row.twin_there_median:g} ({100 * row.twin_there_at_optimum_share:.0f} %) | "
            f"{row.people_lo_median:g}–{row.people_hi_median:g} "
            f"({100 * row.people_hold_optimum_share:.0f} %) |")
    return lines


def fit_text(results: Path) -> str:
    data = _read(results)
    manifest, study = data["manifest"], data["study"]
    rmse, within = manifest["angle_rmse_deg"], manifest["published_conditions_within"]
    factors = ", ".join(f"{name.replace('_', ' ')} ×{value:.2f}"
                        for name, value in manifest["fit_factors"].items())
    total = len(study) // 2
    return (f"Fitted on {manifest['splits']['train']} in-distribution handovers "
            f"({manifest['fit_evaluations']} evaluations of Powell's method): {factors}. The "
            f"angle RMSE over every angle falls from {rmse['default']['train']:.1f}° to "
            f"{rmse['fitted']['train']:.1f}° in training, {rmse['default']['held-out']:.1f}° "
            f"to {rmse['fitted']['held-out']:.1f}° held out ({manifest['splits']['held-out']} "
            f"handovers, receivers possibly shared) and "
            f"{rmse['default']['out-of-distribution']:.1f}° to "
            f"{rmse['fitted']['out-of-distribution']:.1f}° on the "
            f"{manifest['splits']['out-of-distribution']} out-of-distribution recordings. On "
            f"the study's own task the fitted twin meets {within['fitted']} of the {total} "
            f"published conditions, the default twin {within['default']}")


def blocks(results: Path) -> dict[str, str]:
    """Each generated block's text, from ``results``/people/ only."""
    return {"people-headline": headline(results),
            "people-locations": "\n" + "\n".join(locations_table(results)) + "\n",
            "people-calibration": calibration_text(results) + ".",
            "people-skill": "\n" + "\n".join(skill_table(results)) + "\n",
            "people-receiving": "\n" + "\n".join(receiving_table(results)) + "\n",
            "people-recommendation": "\n" + "\n".join(recommendation_table(results)) + "\n",
            "people-fit": fit_text(results) + "."}


def main() -> None:
    """Rewrite the people blocks from results/ wherever each lives."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
