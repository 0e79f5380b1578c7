"""The population study's tables in Markdown, from results/population/ only: what one-size
handover locations cost the workforce against personalised ones, who pays, and how the
optimum's height follows body size. make_tables.py puts them into results/tables.md;
docs/report.md carries them and a test keeps the two equal; ``python population_tables.py``
rewrites the report's blocks."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
from readme_blocks import rewrite

from ergohandover.search.statistics import wilson

CHOICE_NAMES = {"reference": "the 50th-percentile man's optimum",
                "mean": "lowest mean score", "p95": "lowest 95th-percentile score"}
OBJECTIVE_NAMES = {"paper_postural": "postural score", "reba": "REBA", "rula": "RULA"}


def short_source(source: str) -> str:
    """``Magnusson & Ortengren 1987`` from ``Magnusson M, Ortengren R (1987). ...``."""
    authors, year = source.split(" (")[0], source.split(" (")[1][:4]
    return " & ".join(name.split()[0] for name in authors.split(", ")) + f" {year}"


def _read(folder: Path, name: str) -> pd.DataFrame:
    return pd.read_csv(folder / name, keep_default_na=False, na_values=[""])


def interval(mean: float, low: float, high: float, digits: int = 2) -> str:
    """``0.50 (0.17–0.84)``; ``-4.7 (-7.7 to -1.9)`` when the interval has a negative end."""
    dash = " to " if low < 0 else "–"
    return f"{mean:.{digits}f} ({low:.{digits}f}{dash}{high:.{digits}f})"


def share(row, name: str) -> str:
    """``35 % (22–50 %)``: a share with its Wilson interval."""
    return (f"{row[f'share_{name}']:.0%} ({row[f'share_{name}_ci_low']:.0%}–"
            f"{row[f'share_{name}_ci_high']:.0%})")


def one_size_table(one_size: pd.DataFrame) -> list[str]:
    lines = ["| score | one-size location (x, y, z) [m] | chosen as | mean score at it | "
             "workers' own optima, mean | penalty, mean | workers penalised | by 2 or more |",
             "|---|---|---|---|---|---|---|---|"]
    for r in one_size.itertuples():
        row = one_size.loc[r.Index]
        lines.append(
            f"| {OBJECTIVE_NAMES[r.objective]} | ({r.x:.2f}, {r.y:.2f}, {r.z:.2f}) | "
            f"{CHOICE_NAMES[r.choice]} | "
            f"{interval(r.mean_score, r.mean_score_ci_low, r.mean_score_ci_high)} | "
            f"{r.mean_own_optimum:.2f} | "
            f"{interval(r.mean_penalty, r.mean_ci_low, r.mean_ci_high)} | "
            f"{share(row, 'penalised')} | {share(row, 'penalised_2plus')} |"
            + ("" if r.infeasible_for == 0 else f" infeasible for {r.infeasible_for} |"))
    return lines


def who_pays_table(groups: pd.DataFrame, objective: str = "paper_postural") -> list[str]:
    at = groups[groups["objective"] == objective]
    choices = list(dict.fromkeys(at["choice"]))
    lines = ["| workers | n | " + " | ".join(f"penalty at {CHOICE_NAMES[c]}" for c in choices)
             + " |", "|---|---|" + "---|" * len(choices)]
    for (_, group), rows in at.groupby(["by", "group"], sort=False):
        rows = rows.set_index("choice")
        cells = [f"{interval(r.mean_penalty, r.mean_ci_low, r.mean_ci_high)}; "
                 f"{r.share_penalised:.0%} penalised" for r in
                 (rows.loc[c] for c in choices)]
        lines.append(f"| {group} | {int(rows['n'].iloc[0])} | " + " | ".join(cells) + " |")
    return lines


def height_table(fits: pd.DataFrame) -> list[str]:
    lines = ["| score | optimum's height against | slope (95 % CI) | R² | residual SD [cm] | "
             "height above elbow height, mean [cm] (95 % CI) |", "|---|---|---|---|---|---|"]
    at = fits[fits["response"] == "y"].set_index(["objective", "predictor"])
    for objective in dict.fromkeys(fits["objective"]):
        offset = at.loc[(objective, "offset_from_elbow")]
        fit = at.loc[(objective, "stature_m")]
        centimetres = 100 * offset[["mean_offset", "mean_offset_ci_low", "mean_offset_ci_high"]]
        lines.append(
            f"| {OBJECTIVE_NAMES[objective]} | stature | "
            f"{interval(fit.slope, fit.slope_ci_low, fit.slope_ci_high)} | {fit.r2:.2f} | "
            f"{100 * fit.residual_sd:.1f} | "
            f"{interval(*centimetres, digits=1)} |")
    return lines


def working_heights_table(table: pd.DataFrame) -> list[str]:
    lines = ["| hand height below elbow height | published for | source | workers whose "
             "optimum is in it |", "|---|---|---|---|"]
    for r in table.itertuples():
        lines.append(f"| {r.low_cm:g}–{r.high_cm:g} cm | {r.condition} | "
                     f"{short_source(r.source)}{', as quoted' if 'quoted' in r.source else ''}"
                     f" | {r.within}/{r.n}, {r.share:.0%} ({r.ci_low:.0%}–{r.ci_high:.0%}) |")
    return lines


TERM_NAMES = {"stature_m": "stature, per 10 cm", "male": "a man rather than a woman",
              "elbow_ratio": "elbow height / stature, per 0.01",
              "arm_ratio": "arm length / stature, per 0.01"}
TERM_SCALE = {"stature_m": 0.1, "male": 1.0, "elbow_ratio": 0.01, "arm_ratio": 0.01}


def proportions_table(fits: pd.DataFrame, objective: str = "paper_postural") -> list[str]:
    """Penalty against stature, sex and proportions at each one-size location: each term's
    effect in points of the score per the unit named, its 95 % interval and p-value."""
    at = fits[(fits["objective"] == objective) & (fits["term"] != "intercept")]
    choices = list(dict.fromkeys(at["choice"]))
    lines = ["| penalty's change for | " + " | ".join(f"at {CHOICE_NAMES[c]}" for c in choices)
             + " |", "|---|" + "---|" * len(choices)]
    for term in dict.fromkeys(at["term"]):
        cells = []
        for choice in choices:
            r = at[(at["term"] == term) & (at["choice"] == choice)].iloc[0]
            k = TERM_SCALE[term]
            cells.append(f"{interval(k * r.coef, k * r.ci_low, k * r.ci_high)}, p = {r.p:.2g}")
        lines.append(f"| {TERM_NAMES[term]} | " + " | ".join(cells) + " |")
    n = int(at["n"].iloc[0])
    return [*lines, "", f"Least squares over the {n} workers, all four terms together."]


def planned_model(tests: pd.DataFrame) -> str:
    """The plan's model: the one whose rows carry a Holm-adjusted p (who_pays_tests.csv)."""
    return tests.loc[tests["p_holm"].notna(), "model"].iloc[0]


def planned_tests_table(tests: pd.DataFrame) -> list[str]:
    """The plan's family of who-pays tests: per score and distinct one-size location, sex
    beyond body size (points, man less woman) and stature, under the plan's model with Holm's
    adjustment, beside the straight-line fit and the plan's two changes one at a time."""
    if tests.empty:
        return ["No who-pays test: the workers are too few for the plan's models, or nobody's "
                "penalty differs."]
    models = list(dict.fromkeys(tests["model"]))
    planned = planned_model(tests)
    lines = ["| score | one-size location | test | " + " | ".join(
        f"{m}{' (the plan; Holm)' if m == planned else ''}" for m in models) + " |",
        "|---|---|---|" + "---|" * len(models)]
    for (objective, choice, question), rows in tests.groupby(
            ["objective", "choice", "question"], sort=False):
        by = rows.set_index("model")
        cells = []
        for m in models:
            r = by.loc[m]
            p = f"p = {r.p:.2g}" + (f", Holm {r.p_holm:.2g}" if m == planned else "")
            cells.append(f"{r.estimate:+.2f} ({r.ci_low:+.2f} to {r.ci_high:+.2f}), {p}"
                         if question.startswith("sex") else f"F = {r.statistic:.1f}, {p}")
        lines.append(f"| {OBJECTIVE_NAMES[objective]} | {CHOICE_NAMES[choice]} | {question} | "
                     + " | ".join(cells) + " |")
    family = int(tests["family"].iloc[0])
    effects = tests[(tests["model"] == planned) & (tests["p_holm"] < 0.05)]
    return [*lines, "", f"The plan's family: {family} tests over {int(tests['n'].max())} "
            f"workers; {len(effects)} with a Holm-adjusted p below 0.05 ("
            + ", ".join(sorted(set(effects["question"]))) + ")." if len(effects) else
            f"The plan's family: {family} tests; none with a Holm-adjusted p below 0.05."]


def planned_sex(tests: pd.DataFrame, objective: str = "paper_postural",
                choice: str = "reference") -> pd.Series:
    """The plan's sex test at one location (the README's population row)."""
    return tests[(tests["objective"] == objective) & (tests["choice"] == choice)
                 & (tests["question"] == "sex beyond body size")
                 & (tests["model"] == planned_model(tests))].iloc[0]


def fixed_ratio_twin_table(twins: pd.DataFrame) -> list[str]:
    """The reference worker's optimum sized by the survey's model and by the fixed ratios."""
    lines = ["| score | optimum, body model (x, y, z) [m] | optimum, fixed ratios (x, y, z) [m] "
             "| height moved [cm] | reach moved [cm] |", "|---|---|---|---|---|"]
    for objective in dict.fromkeys(twins["objective"]):
        rows = twins[twins["objective"] == objective].set_index("proportions")
        new, old = rows.loc["ansur2"], rows.loc["drillis-contini"]
        lines.append(
            f"| {OBJECTIVE_NAMES[objective]} | {int(new.optimum)} at ({new.x:.2f}, {new.y:.2f}, "
            f"{new.z:.2f}) | {int(old.optimum)} at ({old.x:.2f}, {old.y:.2f}, {old.z:.2f}) | "
            f"{100 * (new.y - old.y):+.0f} | {100 * (new.z - old.z):+.0f} |")
    new, old = (twins[twins["proportions"] == p].iloc[0] for p in ("ansur2", "drillis-contini"))
    return [*lines, "", f"Elbow height {100 * new.elbow_height_m:.1f} cm (the body model's "
            f"standing elbow height) against {100 * old.elbow_height_m:.1f} cm (the fixed "
            "ratios' elbow joint, 0.632 of stature)."]


def claim(one_size: pd.DataFrame, groups: pd.DataFrame, workers: pd.DataFrame) -> str:
    """The report's answer, in one paragraph, for the paper's score."""
    at = one_size[one_size["objective"] == "paper_postural"].set_index("choice")
    sampled = workers[workers["reference"] == 0]
    best = at.loc["mean"]
    ref = at.loc["reference"]
    sex = groups[(groups["objective"] == "paper_postural") & (groups["by"] == "sex")
                 ].set_index(["choice", "group"])
    served = int(sampled["robot_held"].sum())
    low, high = wilson(served, len(sampled))

    def paid(group: str) -> str:
        return interval(*sex.loc[("reference", group), ["mean_penalty", "mean_ci_low",
                                                        "mean_ci_high"]])

    return (f"{len(sampled)} workers ({(sampled['sex'] == 'female').sum()} women), each at their "
            f"own optimum, score {sampled['paper_postural_opt'].mean():.2f} on average. One "
            f"location for everyone, the one of lowest mean score, costs a worker "
            f"{interval(best.mean_penalty, best.mean_ci_low, best.mean_ci_high)} points of the "
            f"postural score on average and penalises {share(best, 'penalised')} of them; the "
            f"50th-percentile man's optimum, what the paper deploys, costs "
            f"{interval(ref.mean_penalty, ref.mean_ci_low, ref.mean_ci_high)} and penalises "
            f"{share(ref, 'penalised')}. There women pay {paid('female')}, men "
            f"{paid('male')}. The robot holds the box at {served} of {len(sampled)} workers' "
            f"own optima ({low:.0%}–{high:.0%}).")


def blocks(results: Path) -> dict[str, str]:
    """Each generated block's text, from ``results``/population/ only."""
    folder = results / "population"
    one_size, groups, fits, workers, heights, proportions, twins, tests = (
        _read(folder, f"{n}.csv") for n in
        ("one_size", "groups", "height_fit", "workers", "working_heights", "proportions",
         "fixed_ratio_twin", "who_pays_tests"))
    table = lambda lines: "\n" + "\n".join(lines) + "\n"  # noqa: E731
    return {"population-claim": claim(one_size, groups, workers),
            "population-one-size": table(one_size_table(one_size)),
            "population-who-pays": table(who_pays_table(groups)),
            "population-height": table(height_table(fits)),
            "population-working-heights": table(working_heights_table(heights)),
            "population-proportions": table(proportions_table(proportions)),
            "population-planned-tests": table(planned_tests_table(tests)),
            "population-fixed-ratio-twin": table(fixed_ratio_twin_table(twins))}


def section(results: Path) -> list[str]:
    """results/tables.md's population section."""
    folder = results / "population"
    manifest = json.loads((folder / "manifest.json").read_text())
    made = blocks(results)
    return [f"## Population: one-size vs personalised handover locations "
            f"({manifest['grid']})", "", made["population-claim"], "",
            "One-size locations and what they cost (95 % intervals):",
            made["population-one-size"], "Who pays (postural score):",
            made["population-who-pays"], "The optimum's height and body size:",
            made["population-height"], made["population-working-heights"],
            "Who pays beyond stature: penalty against sex and proportions (postural score):",
            made["population-proportions"],
            "Who pays, post hoc (planned after the straight-line p = 0.037 was seen; "
            "docs/population.md#the-analysis-plan):",
            made["population-planned-tests"],
            "The reference worker sized by the body model and by the earlier fixed ratios:",
            made["population-fixed-ratio-twin"]]


def main() -> None:
    """Rewrite the population blocks from results/ wherever each lives, README.md or
    docs/report.md (run after the study)."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
