"""What each row of the README's headline table must state, from results/ only: how many
(N), how sure (the uncertainty, or why a figure has none), and the condition under which the
claim reverses or vanishes, where the results hold one. tests/test_headline_rules.py checks
every row against its rule and looks for reversing conditions in the results on its own, so a
rerun that turns up a new one fails until the row names it. The report's table of them is the
block ``headline-rules``; ``python headline_rules.py`` rewrites it."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import pandas as pd
import personalise_tables
import robustness_verdicts
import stance_tables
import workload_tables
from learning_tables import CEILING, verdicts
from population_tables import planned_sex
from readme_blocks import rewrite

MINIMUM_VARIANTS = {
    "no effort task (the straight-legged twin)": "when the twin does not feel the load on its "
                                                 "back, hips and knees",
    "effort free share 7.9% (sustained holds)": "when 7.9 % of its effort is free (sustained "
                                                "holds)"}
"""The sensitivity variants whose minimum differs from the default's, as the row names them."""


@dataclass(frozen=True)
class Rule:
    """One headline row's obligations: fragments its cell must contain.

    Attributes:
        files: the results files its numbers come from.
        n: how many (workers, runs, starts, locations...).
        uncertainty: the interval, or what makes the figure exact.
        reverses: each condition under which it reverses or vanishes; empty where the results
            hold none (``none_because`` says why).
    """

    files: tuple[str, ...]
    n: str
    uncertainty: str
    reverses: tuple[str, ...]
    none_because: str = ""


NUMBERS = {5: "five", 6: "six", 7: "seven", 8: "eight"}
"""How the README writes a small count of simulated workers."""


def stepping_counts(results: Path) -> dict[str, int]:
    """How many of the default worker's starts the optimised location still beats once the
    worker may step, per score (stance/headline.csv)."""
    head = pd.read_csv(results / "stance" / "headline.csv")
    mine = head[(head["optimised_location"] == "optimised") & (head["stance"] == "step")]
    return {s: int(rows["beats"].sum()) for s, rows in mine.groupby("score")}


def rules(results: Path) -> dict[str, Rule]:
    """Every headline row's rule, by its label."""
    stats = pd.read_csv(results / "landscape" / "stats.csv").set_index("score")
    postural = stats.loc["paper_postural"]
    comparisons = pd.read_csv(results / "learning" / "comparisons.csv")
    summary = pd.read_csv(results / "learning" / "summary.csv")
    robust = pd.read_csv(results / "robustness" / "comparisons.csv")
    one_size = pd.read_csv(results / "robustness" / "one_size.csv")
    tests = pd.read_csv(results / "population" / "who_pays_tests.csv")
    workers = pd.read_csv(results / "population" / "workers.csv")
    stance = pd.read_csv(results / "stance" / "headline.csv")
    baselines = pd.read_csv(results / "baselines" / "baselines.csv")
    participants = pd.read_csv(results / "participants" / "participants.csv")
    step = stepping_counts(results)
    posture_sd = stance_tables.ERROR_SD
    starts = len(baselines[["start_x", "start_y", "start_z"]].drop_duplicates())
    measured = pd.read_csv(results / "robustness" / "measured_comparisons.csv")
    clauses = tuple(robustness_verdicts.reversal_clauses(robust, {"comparisons": measured}))
    stepping = (f"once the worker may step, it beats it on REBA from {step['reba']} and on "
                f"RULA from {step['rula']} of {starts} starts")
    q = summary[(summary["agent"] == "qlearning") & (summary["target"] == "paper")
                & (summary["mapping"] == 315.0)].iloc[0]
    walk = comparisons[(comparisons["agent"] == "qlearning")
                       & (comparisons["versus"] == "randomwalk")]
    ceiling = int((verdicts(walk) == CEILING).sum())
    held = one_size[(one_size["objective"] == "paper_postural")
                    & (one_size["choice"] == "mean")].iloc[0]
    sex = planned_sex(tests)
    others = stance[(stance["optimised_location"] == "own optimised") & (stance["score"] == "reba")
                    & (stance["stance"] == "step")]
    handovers = json.loads((results / "people" / "manifest.json").read_text())
    dropped = sum(handovers["dropped"].values())
    advice = pd.read_csv(results / "people" / "recommendation.csv").set_index("score")
    paper_advice, reba_advice = advice.loc["paper_postural"], advice.loc["reba"]
    measured_answers = pd.read_csv(results / "personalise" / "measured_summary.csv")
    inside = measured_answers[measured_answers["model"] == "in-model"]
    outside = measured_answers[measured_answers["model"] == "out-of-model"]
    best_in = personalise_tables.best_measured(
        personalise_tables.own_rule(inside[inside["searcher"] != "random-order"]), "in-model",
        personalise_tables.HEADLINE_ANSWERS, personalise_tables.equal_budget(measured_answers))
    zone = pd.read_csv(results / "accommodation" / "zone.csv").set_index("kind")
    workforce = pd.read_csv(results / "accommodation" / "locations.csv")
    return {
        "the landscape": Rule(
            ("landscape/stats.csv", "landscape/manifest.json"),
            f"{int(postural['points']):,} locations", "one timed run", (),
            "a time on one machine, not a claim that can reverse"),
        "its minimum": Rule(
            ("landscape/stats.csv", "sensitivity/sensitivity.csv"),
            f"on {100 * postural['n_at_min'] / postural['points']:.2f} % of the grid",
            "exact: every location scored", tuple(
                f"{int(v)} {MINIMUM_VARIANTS[k]}" for k, v in pd.read_csv(
                    results / "sensitivity" / "sensitivity.csv").set_index("variant")
                .loc[list(MINIMUM_VARIANTS), "paper_postural_min"].items())),
        "learning": Rule(
            ("learning/summary.csv",),
            f"{int(q['successes'])}/{int(q['n_runs'])}",
            f"({q['ci_low']:.2f}–{q['ci_high']:.2f})", (),
            "success counts at the paper's two budgets, not a comparison; the learning study "
            "compares the learners at every budget and target"),
        "does it learn?": Rule(
            ("learning/comparisons.csv", "learning/power.csv"),
            f"{int(walk['n'].min())} paired runs each", "Holm-corrected",
            (f"in {ceiling} both reach the target in all but at most one run, a ceiling that "
             "tells nothing apart",)),
        "optimised vs shortest distance": Rule(
            ("baselines/baselines.csv", "robustness/comparisons.csv", "stance/headline.csv"),
            f"{starts} starts", "one deterministic twin, no sampling error",
            (*clauses, stepping)),
        "the robot": Rule(
            ("baselines/baselines.csv", "baselines/other_starts.csv",
             "baselines/reachability_summary.csv"),
            f"all {len(baselines)} carries", "seeded planner, one plan each", (),
            "no carry or hold failed"),
        "participants": Rule(
            ("participants/participants.csv", "stance/headline.csv"),
            f"{NUMBERS[participants['worker'].nunique()]} simulated workers",
            "one deterministic twin each",
            (f"once they may step, in {int(others['beats'].sum())} of {len(others)} "
             "comparisons",)),
        "population": Rule(
            ("population/workers.csv", "robustness/one_size.csv",
             "population/who_pays_tests.csv"),
            f"{int((workers['reference'] == 0).sum())} sampled workers",
            f"(95 % of random splits {held['split_half_held_out_q025']:.2f}–"
            f"{held['split_half_held_out_q975']:.2f}",
            ("by body size rather than sex", f"a man's penalty differs from a woman's of the "
             f"same size by {sex['estimate']:+.2f} ({sex['ci_low']:+.2f} to "
             f"{sex['ci_high']:+.2f}; Holm-adjusted p = {sex['p_holm']:.2g}")),
        "under error": Rule(
            ("robustness/measured_comparisons.csv", "robustness/comparisons.csv",
             "robustness/regret.csv", "robustness/personal.csv"),
            f"{int(measured['n'].iloc[0]):,} measurements a location",
            "unadjusted 95 % intervals", clauses),
        "a worker who steps": Rule(
            ("stance/headline.csv", "stance/posture_error.csv"),
            f"from {step['paper_postural']} of {starts} starts on the paper score",
            f"{posture_sd:g}° of posture error (95 % Monte Carlo intervals",
            (f"on REBA from only {step['reba']} and on RULA from {step['rula']}",)),
        "beside people": Rule(
            ("people/manifest.json", "people/recommendation.csv", "people/errors.csv"),
            f"{handovers['handovers']:,} of {handovers['handovers'] + dropped:,} measured "
            "handovers",
            f"quartiles {100 * paper_advice['distance_p25_m']:.0f}–"
            f"{100 * paper_advice['distance_p75_m']:.0f}",
            (f"{int(reba_advice['optimum_cells']):,} cells, REBA hardly tells places apart",)),
        "personalising": Rule(
            ("personalise/measured_summary.csv",),
            f"N = {int(inside['n_workers'].max())} workers, one run each",
            f"({best_in['ci_low']:.0%}–{best_in['ci_high']:.0%})",
            (f"for {int(outside['n_workers'].max())} workers whose twin differs from the "
             "prior's",)),
        "a workforce's zone": Rule(
            ("accommodation/locations.csv", "accommodation/zone.csv"),
            f"N = {int(workforce['workers'].max()):,} workers", "95 % bootstrap intervals",
            (workload_tables.measured_clause(zone),)),
    }


def table(results: Path) -> list[str]:
    """The report's table: each headline row's N, uncertainty and reversing condition."""
    lines = ["| headline row | from | N | uncertainty | reverses or vanishes |",
             "|---|---|---|---|---|"]
    for label, rule in rules(results).items():
        files = ", ".join(f"`{f}`" for f in rule.files)
        lines.append(f"| {label} | {files} | {rule.n} | {rule.uncertainty} | "
                     f"{'; '.join(rule.reverses) or 'none in the results: ' + rule.none_because}"
                     " |")
    return lines


def blocks(results: Path) -> dict[str, str]:
    return {"headline-rules": "\n" + "\n".join(table(results)) + "\n"}


def main() -> None:
    """Rewrite the report's table of headline rules from results/."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
