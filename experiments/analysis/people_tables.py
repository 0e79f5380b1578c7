"""The people part's blocks, from results/people/ only: the README's headline row "beside
people", and the report's tables of where people received, how far the twin predicts their
posture, how far they received from its recommendation, and what the fit of its weights did.
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


def _read(results: Path) -> dict:
    folder = results / "people"
    return {"errors": pd.read_csv(folder / "errors.csv"),
            "locations": pd.read_csv(folder / "locations.csv"),
            "advice": pd.read_csv(folder / "recommendation.csv"),
            "study": pd.read_csv(folder / "study_task.csv"),
            "manifest": json.loads((folder / "manifest.json").read_text())}


def _error(row) -> str:
    return (f"{row.median_abs_deg:.1f} [{row.median_abs_low:.1f}, {row.median_abs_high:.1f}]"
            f" / {row.rmse_deg:.1f} / {row.bias_deg:+.1f}")


def headline(results: Path) -> str:
    """The README's row: N, the held-out median angle errors, how far people received from
    the recommendation, and the fit."""
    data = _read(results)
    manifest, advice = data["manifest"], data["advice"].set_index("score")
    held = data["errors"].query("twin == 'default' and group == 'held-out'").set_index("angle")
    angles = ", ".join(f"{ANGLE_NAMES[a].split(' (')[0]} {held.loc[a, 'median_abs_deg']:.0f}°"
                       for a in ANGLE_NAMES)
    reba, paper = advice.loc["reba"], advice.loc["paper_postural"]
    step = manifest["config"]["people"]["step"]
    total = manifest["handovers"] + sum(manifest["dropped"].values())
    return (f"{manifest['handovers']:,} of {total:,} "
            f"measured handovers (Kim et al. 2025: dynamic, one-handed, small objects, ZED "
            f"keypoints): the twin sized to each receiver, its hand where theirs was, misses "
            f"their angles by a median of {angles} ({int(held['n'].iloc[0])} held out); "
            f"{100 * reba['within_step_share']:.0f} % of people's hands were within one grid "
            f"step ({100 * step:g} cm) of the twin's one-handed REBA optimum "
            f"({int(reba['optimum'])}: {int(reba['optimum_cells']):,} cells, REBA hardly tells "
            f"places apart), a median {100 * paper['distance_median_m']:.0f} cm (quartiles "
            f"{100 * paper['distance_p25_m']:.0f}–{100 * paper['distance_p75_m']:.0f}) from "
            f"the paper score's ({int(paper['optimum'])}), where the twin scores "
            f"{paper['twin_there_median']:g} and people's own measured posture scores "
            f"{_span(paper)}; {fit_clause(data)}")


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
    return (f"fitted weights cut the held-out angle RMSE from {rmse['default']['held-out']:.1f}° "
            f"to {rmse['fitted']['held-out']:.1f}° but are not the default: "
            + (f"{len(bounded)} of them sit at the search's bound, " if bounded else "")
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


def errors_table(results: Path) -> list[str]:
    data = _read(results)
    table = data["errors"].set_index(["twin", "group", "angle"])
    columns = [("default", "held-out"), ("fitted", "held-out"),
               ("default", "out-of-distribution"), ("fitted", "out-of-distribution")]
    n = {group: int(table.loc[("default", group, "trunk_flexion"), "n"])
         for group in ("held-out", "out-of-distribution")}
    lines = ["| angle | " + " | ".join(f"{twin} twin, {group} (N = {n[group]})"
                                        for twin, group in columns) + " |",
             "|---|" + "---|" * len(columns)]
    for angle, name in ANGLE_NAMES.items():
        cells = [_error(table.loc[(twin, group, angle)]) for twin, group in columns]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return [*lines, "", "Each cell: median |predicted − measured| [95 % bootstrap interval] / "
            "RMSE / bias (mean predicted − measured), degrees."]


def recommendation_table(results: Path) -> list[str]:
    data = _read(results)
    lines = ["| score | the twin's optimum (x, y, z) [m] (cells at it) | people's hands from the "
             "nearest optimal cell: median (quartiles) [cm] | within one grid step | the twin "
             "where people received: median (at its optimum) | people's measured score: "
             "median interval (holds the optimum) |", "|---|---|---|---|---|---|"]
    for row in data["advice"].itertuples():
        lines.append(
            f"| {SCORE_NAMES[row.score]} | {row.optimum} at ({row.optimum_x:.2f}, "
            f"{row.optimum_y:.2f}, {row.optimum_z:.2f}) ({row.optimum_cells:,}) | "
            f"{100 * row.distance_median_m:.0f} ({100 * row.distance_p25_m:.0f}–"
            f"{100 * row.distance_p75_m:.0f}) | {100 * row.within_step_share:.0f} % | "
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
            "people-errors": "\n" + "\n".join(errors_table(results)) + "\n",
            "people-recommendation": "\n" + "\n".join(recommendation_table(results)) + "\n",
            "people-fit": fit_text(results) + "."}


def main() -> None:
    """Rewrite the people blocks from results/ wherever each lives."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
