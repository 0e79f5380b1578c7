"""The robustness part's blocks of docs/report.md, from results/robustness/ only: the claim, the
headline locations under posture error, the comparisons that do and do not survive, regret, the
one-size choices without optimism and the placement error. ``python robustness_tables.py``
rewrites them after the study."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
from readme_blocks import rewrite

SCORE_NAMES = {"paper_postural": "paper", "reba": "REBA", "rula": "RULA"}
POSTURE_IMU_SOURCE = ("Schall MC, Fethke NB, Chen H, Oyama S, Douphrate DI (2016). Accuracy and "
                      "repeatability of an inertial measurement unit system for field-based "
                      "occupational studies. Ergonomics 59(4):591-602")
"""IMUs against optical motion capture: RMS differences of 4.1-6.6 deg for the trunk and
7.2-12.1 deg for the upper arm (its Table 2)."""


def _read(results: Path, name: str) -> pd.DataFrame:
    return pd.read_csv(results / "robustness" / name)


def _interval(row, digits: int = 2) -> str:
    return f"{row['difference']:+.{digits}f} ({row['ci_low']:+.{digits}f} to " \
           f"{row['ci_high']:+.{digits}f})"


def claim(locations, comparisons, regret, one_size, regression) -> str:
    paper = locations[locations["score"] == "paper_postural"].set_index(
        ["location", "angle_sd_deg"])
    nominal, robust = paper.loc[("nominal optimum", 5.0)], paper.loc[("robust optimum", 5.0)]
    at5 = comparisons[(comparisons["perturbation"] == "posture error")
                      & (comparisons["angle_sd_deg"] == 5.0) & (comparisons["a"] ==
                                                                "nominal optimum")]
    short = lambda c, s: c[(c["score"] == s) & c["b"].str.startswith("shortest")]  # noqa: E731
    variants = comparisons[(comparisons["perturbation"] == "model variants")
                           & (comparisons["a"] == "nominal optimum")]
    rs = regret[(regret["recommendation"] == "nominal optimum")
                & (regret["score"] == "paper_postural")].set_index("source")
    mean = one_size[(one_size["objective"] == "paper_postural")
                    & (one_size["choice"] == "mean")].iloc[0]
    sex = regression[(regression["objective"] == "paper_postural")
                     & (regression["choice"] == "reference")
                     & (regression["term"] == "male")].iloc[0]
    return (
        f"At 5° of error on every measured angle (an IMU's accuracy: Schall et al. 2016 measured "
        f"4.1–6.6° for the trunk and 7.2–12.1° for the upper arm), the nominal optimum's paper "
        f"score of {int(nominal['nominal'])} is measured as {int(nominal['nominal'])} or better "
        f"in {100 * nominal['p_nominal_or_better']:.1f} % of measurements (mean "
        f"{nominal['mean']:.2f}). The robust optimum scores {int(robust['nominal'])} without "
        f"error and {robust['mean']:.2f} at 5°, {nominal['mean'] - robust['mean']:.2f} lower. "
        f"The nominal optimum still beats the shortest-distance location on the paper score "
        f"from {int(short(at5, 'paper_postural')['survives'].sum())} of "
        f"{len(short(at5, 'paper_postural'))} starts at 5° and on REBA from "
        f"{int(short(at5, 'reba')['survives'].sum())}; across the "
        f"{int(variants['n'].max())} model variants it beats them from "
        f"{int(short(variants, 'paper_postural')['survives'].sum())} of "
        f"{len(short(variants, 'paper_postural'))}. Its regret on the paper score is "
        f"{rs.loc['sensitivity', 'mean_regret']:.2f} on average over the model variants "
        f"(worst {rs.loc['sensitivity', 'max_regret']:.0f}) and "
        f"{rs.loc['population', 'mean_regret']:.2f} over the {int(rs.loc['population', 'n'])} "
        f"workers (worst {rs.loc['population', 'max_regret']:.0f}). The one-size location of "
        f"lowest mean costs {mean['in_sample_mean_penalty']:.2f} in sample, "
        f"{mean['rechosen_mean_penalty']:.2f} ({mean['rechosen_ci_low']:.2f}–"
        f"{mean['rechosen_ci_high']:.2f}) when re-chosen in every bootstrap resample and "
        f"{mean['split_half_held_out']:.2f} on workers it was not chosen on (split halves). "
        f"At the reference's optimum, with stature in the model, men pay {sex['coef']:+.2f} "
        f"({sex['ci_low']:+.2f} to {sex['ci_high']:+.2f}, p = {sex['p']:.2g}) points of "
        f"penalty more than women of the same stature.")


def headline(locations, comparisons, regret, one_size) -> str:
    """The README's headline cell: what survives posture error, the model variants and the
    workers."""
    paper = locations[locations["score"] == "paper_postural"].set_index(
        ["location", "angle_sd_deg"])
    nominal, robust = paper.loc[("nominal optimum", 5.0)], paper.loc[("robust optimum", 5.0)]

    def kept(perturbation, score, sd=None):
        rows = comparisons[(comparisons["perturbation"] == perturbation)
                           & (comparisons["a"] == "nominal optimum")
                           & (comparisons["score"] == score)
                           & comparisons["b"].str.startswith("shortest")]
        if sd is not None:
            rows = rows[rows["angle_sd_deg"] == sd]
        return f"{int(rows['survives'].sum())} of {len(rows)}"

    rs = regret[(regret["recommendation"] == "nominal optimum")
                & (regret["score"] == "paper_postural")].set_index("source")
    mean = one_size[(one_size["objective"] == "paper_postural")
                    & (one_size["choice"] == "mean")].iloc[0]
    return (f"with 5° of error on every measured angle the optimum's {int(nominal['nominal'])} "
            f"is measured as such {100 * nominal['p_nominal_or_better']:.1f} % of the time; it "
            f"still beats the shortest-distance location in expectation from "
            f"{kept('posture error', 'paper_postural', 2.0)} starts at 2° and "
            f"{kept('posture error', 'paper_postural', 5.0)} at 5° on the paper score, "
            f"{kept('posture error', 'reba', 5.0)} on REBA at 5°, and "
            f"{kept('model variants', 'paper_postural')} across the model variants; a robust "
            f"optimum (error-free score {int(robust['nominal'])}) expects {robust['mean']:.2f} "
            f"at 5° against the optimum's {nominal['mean']:.2f}; the optimum's regret is "
            f"{rs.loc['sensitivity', 'mean_regret']:.2f} over {int(rs.loc['sensitivity', 'n'])} "
            f"model variants and {rs.loc['population', 'mean_regret']:.2f} over "
            f"{int(rs.loc['population', 'n'])} workers; the one-size location costs "
            f"{mean['split_half_held_out']:.2f} on workers it was not chosen on")


def locations_table(locations) -> list[str]:
    wide = locations[locations["angle_sd_deg"].isin((2.0, 5.0))]
    lines = ["| location (x, y, z) [m] | score | error-free | mean at 2° | mean at 5° | "
             "P(≤ error-free) at 5° | 5th–95th percentile at 5° |", "|---|---|---|---|---|---|---|"]
    for (name, score), rows in wide.groupby(["location", "score"], sort=False):
        r2, r5 = (rows[rows["angle_sd_deg"] == sd].iloc[0] for sd in (2.0, 5.0))
        lines.append(f"| {name} ({r5['x']:.3f}, {r5['y']:.3f}, {r5['z']:.3f}) | "
                     f"{SCORE_NAMES[score]} | {int(r5['nominal'])} | {r2['mean']:.2f} | "
                     f"{r5['mean']:.2f} | {100 * r5['p_nominal_or_better']:.1f} % | "
                     f"{int(r5['q05'])}–{int(r5['q95'])} |")
    return lines


def comparisons_table(comparisons) -> list[str]:
    lines = ["| comparison | score | posture error 2° | posture error 5° | model variants |",
             "|---|---|---|---|---|"]
    keyed = comparisons.assign(angle=comparisons["angle_sd_deg"].fillna(-1))
    pairs = keyed[keyed["perturbation"] == "posture error"][["comparison", "score"]]
    for _, (comparison, score) in pairs.drop_duplicates().iterrows():
        cells = []
        for perturbation, angle in (("posture error", 2.0), ("posture error", 5.0),
                                    ("model variants", -1)):
            row = keyed[(keyed["comparison"] == comparison) & (keyed["score"] == score)
                        & (keyed["perturbation"] == perturbation) & (keyed["angle"] == angle)]
            cells.append("–" if row.empty else
                         f"{_interval(row.iloc[0])} {'yes' if row.iloc[0]['survives'] else 'no'}")
        lines.append(f"| {comparison} | {SCORE_NAMES[score]} | " + " | ".join(cells) + " |")
    workers = comparisons[comparisons["perturbation"] == "posture error, workers"]
    for _, row in workers.iterrows():
        lines.append(f"| {row['comparison']} ({int(row['n'])} workers, posture error "
                     f"{row['angle_sd_deg']:g}°) | paper | {_interval(row)} "
                     f"{'yes' if row['survives'] else 'no'} | | |")
    return lines


def regret_table(summary) -> list[str]:
    lines = ["| over | recommendation | score | N | mean regret (95 %) | worst | no regret |",
             "|---|---|---|---|---|---|---|"]
    for _, r in summary.iterrows():
        lines.append(f"| {r['source']} | {r['recommendation']} | {SCORE_NAMES[r['score']]} | "
                     f"{int(r['n'])} | {r['mean_regret']:.2f} ({r['ci_low']:.2f}–"
                     f"{r['ci_high']:.2f}) | {r['max_regret']:.0f} | "
                     f"{100 * r['share_no_regret']:.0f} % |")
    return lines


def one_size_table(one_size) -> list[str]:
    lines = ["| score | one-size choice | in sample | re-chosen in the bootstrap (95 %) | "
             "held-out half (95 % of splits) | optimism |", "|---|---|---|---|---|---|"]
    for _, r in one_size.iterrows():
        lines.append(f"| {SCORE_NAMES[r['objective']]} | {r['choice']} | "
                     f"{r['in_sample_mean_penalty']:.2f} | {r['rechosen_mean_penalty']:.2f} "
                     f"({r['rechosen_ci_low']:.2f}–{r['rechosen_ci_high']:.2f}) | "
                     f"{r['split_half_held_out']:.2f} ({r['split_half_held_out_q025']:.2f}–"
                     f"{r['split_half_held_out_q975']:.2f}) | {r['optimism']:+.2f} |")
    return lines


def placement_table(placement) -> list[str]:
    paper = placement[placement["score"] == "paper_postural"]
    radii = sorted(paper["radius_cm"].unique())
    lines = ["| location | " + " | ".join(f"{r:g} cm" for r in radii) + " |",
             "|---|" + "---|" * len(radii)]
    for name, rows in paper.groupby("location", sort=False):
        lines.append(f"| {name} | " + " | ".join(
            f"{rows[rows['radius_cm'] == r]['mean'].iloc[0]:.2f}" for r in radii) + " |")
    return lines


def practice_carries(carries) -> str:
    """Whether the robot serves the practice location from the paper's starts, in one line."""
    served = carries[carries["robot_feasible"] == 1]
    text = (f"The robot carries the box to the practice location from {len(served)} of "
            f"{len(carries)} of the paper's starts")
    if len(served):
        text += (f" (paths {served['path_length_m'].min():.2f}–"
                 f"{served['path_length_m'].max():.2f} m, clearance to the worker at least "
                 f"{100 * served['clearance_m'].min():.1f} cm, planned in "
                 f"{served['planning_s'].min():.1f}–{served['planning_s'].max():.1f} s; "
                 "`practice_carries.csv`)")
    missed = carries[carries["robot_feasible"] == 0]
    if len(missed):
        text += "; not from " + ", ".join(
            f"({r.start_x:.3f}, {r.start_y:.3f}, {r.start_z:.3f}): {r.robot_reason}"
            for r in missed.itertuples())
    return text + "."


def blocks(results: Path) -> dict[str, str]:
    """Each generated block's text, from ``results``/robustness/ only."""
    locations, comparisons, summary, one_size, regression, placement, carries = (
        _read(results, f"{n}.csv") for n in ("locations", "comparisons", "regret_summary",
                                              "one_size", "penalty_regression", "placement",
                                              "practice_carries"))
    table = lambda lines: "\n" + "\n".join(lines) + "\n"  # noqa: E731
    return {"robustness-headline": headline(locations, comparisons, summary, one_size),
            "robustness-claim": claim(locations, comparisons, summary, one_size, regression),
            "robustness-locations": table(locations_table(locations)),
            "robustness-comparisons": table(comparisons_table(comparisons)),
            "robustness-regret": table(regret_table(summary)),
            "robustness-one-size": table(one_size_table(one_size)),
            "robustness-placement": table(placement_table(placement)),
            "robustness-practice-carries": practice_carries(carries)}


def main() -> None:
    """Rewrite the robustness blocks from results/ wherever each lives (run after the study)."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
