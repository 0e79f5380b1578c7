"""The study's headlines, declared: each README row holds a claim, its N, its uncertainty, the
baseline it is compared with (what a user gets without this tool's answer) and the conditions
under which it reverses or vanishes, every figure read from results/. The README's headline
table (block ``headlines``) and the report's table of them (block ``headline-rules``) are
rendered from these declarations; ``python headlines.py`` rewrites both, and
tests/test_readme.py and tests/test_headline_rules.py keep them equal to results/.

Each headline names the question of the study registry (ergohandover.study.registry) that
answers it."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import people_tables
import personalise_tables
import robustness_verdicts
import shift_tables
import stance_tables
from headline_types import Headline, exact_interval, pct
from learning_tables import CEILING, verdicts
from population_tables import planned_sex
from readme_blocks import rewrite
from stance_tables import span

CELL = 250
"""The most characters a README cell holds; the rest is in the report, one link away."""

MINIMUM_VARIANTS = {
    "no effort task (the straight-legged twin)": "when the twin does not feel the load on its "
                                                 "back, hips and knees",
    "effort free share 7.9% (sustained holds)": "when 7.9 % of its effort is free (sustained "
                                                "holds)"}
"""The sensitivity variants whose minimum differs from the default's, as the row names them."""


def beaten_starts(results: Path, stance: str = "step") -> dict[str, int]:
    """How many of the default worker's starts the optimised location beats the
    shortest-distance one from, per score, when the worker stands as ``stance`` says (``step``:
    may step; ``fixed``: planted; stance/headline.csv)."""
    head = pd.read_csv(results / "stance" / "headline.csv")
    mine = head[(head["optimised_location"] == "optimised") & (head["stance"] == stance)]
    return {s: int(rows["beats"].sum()) for s, rows in mine.groupby("score")}


def landscape_rows(results: Path) -> list[Headline]:
    stats = pd.read_csv(results / "landscape" / "stats.csv").set_index("score")
    post = stats.loc["paper_postural"]
    manifest = json.loads((results / "landscape" / "manifest.json").read_text())
    minutes = manifest["sweep_seconds"] / 60
    moved = pd.read_csv(results / "sensitivity" / "sensitivity.csv").set_index("variant").loc[
        list(MINIMUM_VARIANTS), "paper_postural_min"]
    share = 100 * post["n_at_min"] / post["points"]
    return [
        Headline("landscape", "the landscape", "the-exhaustive-landscape",
                 "evaluating every location of the grid (~3.4 M) takes ~3 h",
                 f"every location scored in {minutes:.1f} min on 2 cores",
                 f"{int(post['points']):,} locations", "one timed run",
                 "the paper's Unity evaluation: ~3 h", (),
                 "a time on one machine, not a claim that can reverse",
                 ("landscape/stats.csv", "landscape/manifest.json")),
        Headline("landscape", "its minimum", "the-exhaustive-landscape",
                 "most of the landscape scores 6–7; 0.004 % reaches the minimum, 4",
                 f"the minimum is {int(post['min'])}, on {share:.2f} % of the grid",
                 f"{int(post['points']):,} locations", "exact: every location scored",
                 "the paper's 4 on 0.004 %",
                 tuple(f"{int(v)} {MINIMUM_VARIANTS[k]}" for k, v in moved.items()), "",
                 ("landscape/stats.csv", "sensitivity/sensitivity.csv")),
    ]


def learning_rows(results: Path) -> list[Headline]:
    summary = pd.read_csv(results / "learning" / "summary.csv")
    comparisons = pd.read_csv(results / "learning" / "comparisons.csv")
    mine = summary[(summary["target"] == "paper") & (summary["mapping"] == 315.0)]

    def rate(agent: str) -> pd.DataFrame:
        return mine[mine["agent"] == agent].sort_values("steps")

    def counts(rows: pd.DataFrame) -> str:
        return " and ".join(f"{int(r['successes'])}/{int(r['n_runs'])}"
                            for _, r in rows.iterrows())

    q, draws = rate("qlearning"), rate("random-draws")
    intervals = ", ".join(f"{r['ci_low']:.2f}–{r['ci_high']:.2f}" for _, r in q.iterrows())
    walk = comparisons[(comparisons["agent"] == "qlearning")
                       & (comparisons["versus"] == "randomwalk")]
    drawn = comparisons[(comparisons["agent"] == "qlearning")
                        & (comparisons["versus"] == "random-draws")]
    better = int(walk["verdict"].str.startswith("better").sum())
    better_draws = int(drawn["verdict"].str.startswith("better").sum())
    worse_draws = int(drawn["verdict"].str.startswith("worse").sum())
    ceiling = int((verdicts(walk) == CEILING).sum())
    return [
        Headline("learning", "learning", "the-learning-study-can-the-learners-be-told-apart",
                 "10 Q-learning runs at 2 min and 10 at 5 min all reach the global minimum",
                 f"Q-learning reaches the minimum in {counts(q)} runs at the paper's two caps",
                 f"{int(q['n_runs'].iloc[0])} runs a cap", f"95 % Wilson {intervals}",
                 f"random draws: {counts(draws)}", (),
                 "success counts at the paper's two budgets, not a comparison (next row)",
                 ("learning/summary.csv",)),
        Headline("learning", "does it learn?",
                 "the-learning-study-can-the-learners-be-told-apart",
                 "Q-learning learns where to hand over",
                 f"Q-learning beats a random walk in {better} of {len(walk)} comparisons and "
                 f"random draws in {better_draws} of {len(drawn)} (worse in {worse_draws})",
                 f"{int(walk['n'].min())} paired runs each", "Holm-corrected",
                 "a random walk; random draws",
                 (f"in {ceiling} both reach the target in all but at most one run, a ceiling "
                  "that tells nothing apart",), "",
                 ("learning/comparisons.csv", "learning/power.csv")),
    ]


def robot_rows(results: Path) -> list[Headline]:
    baselines = pd.read_csv(results / "baselines" / "baselines.csv")
    others = pd.read_csv(results / "baselines" / "other_starts.csv")
    reach = pd.read_csv(results / "baselines" / "reachability_summary.csv").iloc[0]
    robust = pd.read_csv(results / "robustness" / "comparisons.csv")
    measured = pd.read_csv(results / "robustness" / "measured_comparisons.csv")
    clauses = tuple(robustness_verdicts.reversal_clauses(robust, {"comparisons": measured}))
    step = beaten_starts(results)
    starts = len(baselines[["start_x", "start_y", "start_z"]].drop_duplicates())
    opt = baselines[baselines["method"] == "optimised"]
    near = baselines[baselines["method"] == "shortest_distance"]
    return [
        Headline("baselines", "optimised vs shortest distance", "robot-and-baselines",
                 "the optimised location beats the shortest-distance one from all five starts",
                 f"paper score {span(opt['paper_postural'])} vs "
                 f"{span(near['paper_postural'])}, REBA {span(opt['reba'])} vs "
                 f"{span(near['reba'])}, RULA {span(opt['rula'])} vs {span(near['rula'])}",
                 f"{starts} starts", "one deterministic twin, no sampling error",
                 f"the shortest-distance location: paper score {span(near['paper_postural'])}",
                 (*clauses, f"once the worker may step, it beats it on REBA from {step['reba']} "
                  f"and on RULA from {step['rula']} of {starts} starts"), "",
                 ("baselines/baselines.csv", "robustness/comparisons.csv",
                  "stance/headline.csv")),
        Headline("baselines", "the robot", "robot-and-baselines",
                 "the box moves freely in Unity",
                 f"two Panda arms on a lift and base carry the box clear of the worker: "
                 f"{int(baselines['robot_feasible'].sum())} of {len(baselines)} carries, "
                 f"{int(others['robot_feasible'].sum())} of {len(others)} more starts; it holds "
                 f"the box at {int(reach['held']):,} of {int(reach['locations']):,} grid "
                 "locations",
                 f"{len(baselines) + len(others)} carries",
                 "seeded planner, one plan each", "a box that moves itself (the paper)", (),
                 "no carry or hold failed",
                 ("baselines/baselines.csv", "baselines/other_starts.csv",
                  "baselines/reachability_summary.csv")),
    ]


NUMBERS = {5: "five", 6: "six", 7: "seven", 8: "eight"}


def participant_rows(results: Path) -> list[Headline]:
    table = pd.read_csv(results / "participants" / "participants.csv")
    stance = pd.read_csv(results / "stance" / "headline.csv")
    own = table[table["location"] == "own-optimised"]
    near = table[table["location"] == "shortest-distance"]
    others = stance[(stance["optimised_location"] == "own optimised")
                    & (stance["score"] == "reba") & (stance["stance"] == "step")]
    return [Headline(
        "participants", "participants", "where-and-why-we-differ-from-the-paper",
        "five VR participants: lower REBA at the optimised location from both starts",
        f"REBA {span(own['reba'])} at each worker's own optimum vs {span(near['reba'])} at the "
        "shortest-distance locations",
        f"{NUMBERS[table['worker'].nunique()]} simulated workers",
        "one deterministic twin each", f"the shortest-distance locations: REBA "
        f"{span(near['reba'])}",
        (f"once they may step, in {int(others['beats'].sum())} of {len(others)} comparisons",),
        "", ("participants/participants.csv", "stance/headline.csv"))]


def population_rows(results: Path) -> list[Headline]:
    one_size = pd.read_csv(results / "robustness" / "one_size.csv")
    tests = pd.read_csv(results / "population" / "who_pays_tests.csv")
    workers = pd.read_csv(results / "population" / "workers.csv")
    rows = one_size[one_size["objective"] == "paper_postural"].set_index("choice")
    held, ref = rows.loc["mean"], rows.loc["reference"]
    sex = planned_sex(tests)
    return [Headline(
        "population", "population", "population-one-location-for-everyone-or-one-per-worker",
        "personalisation named as future work",
        f"one location for everyone (the lowest mean) costs {held['split_half_held_out']:.2f} "
        "points of the paper score held out against each worker's own optimum",
        f"{int((workers['reference'] == 0).sum())} sampled workers",
        f"95 % of random splits {held['split_half_held_out_q025']:.2f}–"
        f"{held['split_half_held_out_q975']:.2f}",
        f"the 50th-percentile man's optimum, chosen on no worker: "
        f"{ref['in_sample_mean_penalty']:.2f}",
        (f"post hoc, a man's penalty differs from a woman's of the same size by "
         f"{sex['estimate']:+.2f} ({sex['ci_low']:+.2f} to {sex['ci_high']:+.2f}), "
         "an interval that allows a sex effect",), "",
        ("population/workers.csv", "robustness/one_size.csv",
         "population/who_pays_tests.csv"))]


def robustness_rows(results: Path) -> list[Headline]:
    robust = pd.read_csv(results / "robustness" / "comparisons.csv")
    measured = pd.read_csv(results / "robustness" / "measured_comparisons.csv")
    clauses = tuple(robustness_verdicts.reversal_clauses(robust, {"comparisons": measured}))
    head = robustness_verdicts.headline_model({"comparisons": measured})["comparisons"]
    rows = robustness_verdicts.shortest(head)
    better = {s: int((g["ci_high"] < 0).sum()) for s, g in rows.groupby("score")}
    starts = rows["b"].nunique()
    return [Headline(
        "robustness", "under error",
        "robustness-does-the-recommendation-survive-being-measured",
        "one exact score per location, no measurement error",
        f"under an IMU-like error model (4 of its 15 SDs measured, the rest assumed), the "
        f"optimum is expected better than shortest distance on REBA from {better['reba']}, "
        f"RULA {better['rula']}, the paper score {better['paper_postural']} of {starts} starts",
        f"{int(measured['n'].iloc[0]):,} measurements a location",
        "unadjusted 95 % intervals", "the error-free comparison: better from every start",
        clauses, "", ("robustness/measured_comparisons.csv", "robustness/comparisons.csv"))]


def stance_rows(results: Path) -> list[Headline]:
    step, kept = beaten_starts(results), beaten_starts(results, "fixed")
    head = pd.read_csv(results / "stance" / "headline.csv")
    starts = head[(head["optimised_location"] == "optimised")]["start"].nunique()
    return [Headline(
        "stance", "a worker who steps", "a-worker-who-can-step", "the worker's feet stay planted",
        f"once the worker may step, the optimum still beats shortest distance on the paper score "
        f"from {step['paper_postural']} of {starts} starts",
        f"{starts} starts", f"{stance_tables.ERROR_SD:g}° of posture error: 95 % Monte Carlo "
        "intervals", f"the planted worker: from {kept['paper_postural']} of {starts}",
        (f"on REBA from only {step['reba']} and on RULA from {step['rula']}",), "",
        ("stance/headline.csv", "stance/posture_error.csv"))]


def people_rows(results: Path) -> list[Headline]:
    manifest = json.loads((results / "people" / "manifest.json").read_text())
    held, out = people_tables.pooled(results), people_tables.pooled(results,
                                                                     "out-of-distribution")
    ours = held.loc["line + twin"]
    ranking = pd.read_csv(results / "people" / "ranking.csv").set_index(["score", "group"])
    reba = ranking.loc[("reba", "held-out")]
    return [Headline(
        "people", "beside people", "the-twin-beside-a-thousand-measured-handovers",
        "no measured handover; five VR participants",
        f"held out, the twin's angle, with the hand's place and stature in a straight line, "
        f"predicts receivers' six angles with skill {ours['skill']:+.2f} against the "
        f"constant (RMSE {ours['rmse_deg']:.1f}° vs {held.loc['constant', 'rmse_deg']:.1f}°)",
        f"{int(ours['n']) // 6} of {manifest['handovers']:,} handovers",
        f"95 % bootstrap {ours['skill_low']:+.2f} to {ours['skill_high']:+.2f}; noise ceiling "
        f"{ours['ceiling_rmse_deg']:.1f}°",
        f"the training mean ({held.loc['constant', 'rmse_deg']:.1f}°); the line without the "
        f"twin ({held.loc['line', 'rmse_deg']:.1f}°, skill {held.loc['line', 'skill']:+.2f})",
        (f"the twin alone is worse than the constant (skill {held.loc['twin', 'skill']:+.2f}: "
         "it stands and looks down, the receivers walk, head up)",
         f"out of distribution skill falls to {out.loc['line + twin', 'skill']:+.2f}",
         f"its scores do not rank people's (REBA Spearman {reba['spearman']:.2f})"), "",
        ("people/skill.csv", "people/ranking.csv", "people/manifest.json"))]


def answered(answers: str) -> str:
    """An answer model's label (measured_answers.py) as the words after "answered"."""
    if answers.startswith("posture SD "):
        return f"with postures at {answers.split()[2]}° of error"
    if answers.startswith("rater ICC "):
        return f"by a rater of ICC {answers.split()[2]}"
    return f"by {answers}"


def personalise_rows(results: Path) -> list[Headline]:
    measured = pd.read_csv(results / "personalise" / "measured_summary.csv")
    answers, budget = personalise_tables.HEADLINE_ANSWERS, personalise_tables.HEADLINE_BUDGET
    mine = personalise_tables.own_rule(measured[measured["searcher"] != "random-order"])
    best = personalise_tables.best_measured(mine, "in-model", answers, budget)
    nothing = personalise_tables.at(measured, "in-model", answers, "no search",
                                    "prior's location", 1)
    # Out of model, the answers under which its gain's lower bound is lowest.
    out = min((personalise_tables.at(measured, "out-of-model", a, best["searcher"],
                                     best["rule"], budget)
               for a in measured["answers"].unique() if a != "exact"),
              key=lambda row: row["gain_ci_low"])
    runs = int(best["n_runs"]) // int(best["n_workers"])
    reversal = [f"out of model ({int(out['n_workers'])} workers whose twin differs), answered "
                f"{answered(out['answers'])}, the gain's interval reaches "
                f"{personalise_tables.bound(out['gain_ci_low'])} and {pct(out['harm'])} of runs "
                "are worse than no search"]
    reversal += personalise_tables.other_reversals(measured, best)
    reversal.append(f"its model states {pct(best['model_p_optimal'])} for the "
                    f"{pct(best['p_regret_0'])} it finds")
    return [Headline(
        "personalise", "personalising",
        "personalisation-how-many-handovers-to-find-one-workers-optimum",
        "deep Q-learning and Soft Actor-Critic named as future work",
        f"postures measured with 5° of error, {budget} handovers: "
        f"{personalise_tables.label(best['searcher'])} gains "
        f"{best['gain']:+.2f} points of true regret over no search; the worker's true optimum "
        f"in {pct(best['p_regret_0'])} of runs, harm {pct(best['harm'])}",
        f"N = {int(best['n_workers'])} workers, {runs} runs each",
        f"gain 95 % {best['gain_ci_low']:+.2f} to {best['gain_ci_high']:+.2f}; optimum "
        f"{pct(best['ci_low'])}–{pct(best['ci_high'])}",
        f"no search, one handover at the prior's location: the optimum in "
        f"{pct(nothing['p_regret_0'])} ({pct(nothing['ci_low'])}–{pct(nothing['ci_high'])})",
        tuple(reversal), "", ("personalise/measured_summary.csv",))]


def accommodation_rows(results: Path) -> list[Headline]:
    at = pd.read_csv(results / "accommodation" / "locations.csv")
    zone = pd.read_csv(results / "accommodation" / "zone.csv").set_index("kind")
    rec = at[at["location"] == "nominal optimum"].iloc[0]
    n = int(rec["workers"])
    suited = round(rec["exact_share"] * n)
    low, high = exact_interval(suited, n)
    measured = zone.loc["measured"]
    return [Headline(
        "accommodation", "a workforce's zone", "the-practitioners-outputs", "not studied",
        f"error-free, REBA ≤ 3 and RULA ≤ 4 hold at the recommended location for {suited:,} of "
        f"{n:,} workers; " + (
            f"one IMU-like measurement agrees in {pct(rec['measured_share'])} of "
            f"measurements (misclassifies {pct(1 - rec['measured_share'])})" if suited == n
            else f"one IMU-like measurement passes a worker in {pct(rec['measured_share'])} of "
            "measurements"),
        f"N = {n:,} workers", f"exact 95 % {pct(low)}–{pct(high)}",
        "the error-free score", (f"as measured, no point serves {pct(measured['share'])} of "
                                  f"the workforce (the best {pct(measured['best_share'])})",)
        if int(measured["cells"]) == 0 else (), "none: the measured zone serves its share",
        ("accommodation/locations.csv", "accommodation/zone.csv"))]


def headlines(results: Path) -> list[Headline]:
    """Every headline, in the README's order."""
    return [*landscape_rows(results), *learning_rows(results), *robot_rows(results),
            *participant_rows(results), *population_rows(results),
            *robustness_rows(results), *stance_rows(results), *people_rows(results),
            *personalise_rows(results), *accommodation_rows(results),
            *shift_tables.shift_rows(results)]


def fitted(parts: list[str], limit: int = CELL, more: str = "") -> str:
    """``parts`` joined by "; ", as many as fit in ``limit`` characters, the rest counted in
    ``more`` (a link to where they are listed)."""
    text = ""
    for k, part in enumerate(parts):
        rest = len(parts) - k - 1
        tail = f"; and {rest} more {more}" if rest else ""
        candidate = f"{text}; {part}" if text else part
        if len(candidate) + len(tail) > limit:
            return f"{text}; and {len(parts) - k} more {more}" if text else \
                f"{len(parts)} conditions {more}"
        text = candidate
    return text


def cells(h: Headline) -> list[str]:
    """The row's cells: label, the paper, the claim with N and uncertainty, the baseline,
    what reverses it."""
    link = "([all](docs/report.md#what-each-headline-rests-on))"
    return [f"[{h.label}](docs/report.md#{h.anchor})", h.paper,
            f"{h.claim} ({h.n}; {h.uncertainty})", h.baseline,
            fitted(list(h.reverses), more=link) if h.reverses else f"none: {h.none_because}"]


def readme_table(results: Path) -> list[str]:
    lines = ["| | the paper | we measured (N; uncertainty) | compared with | reverses or "
             "vanishes when |", "|---|---|---|---|---|"]
    lines += ["| " + " | ".join(cells(h)) + " |" for h in headlines(results)]
    return lines


def report_table(results: Path) -> list[str]:
    """The report's table: each headline with every reversing condition and its files."""
    lines = ["| headline row | from | N | uncertainty | compared with | reverses or vanishes |",
             "|---|---|---|---|---|---|"]
    for h in headlines(results):
        files = ", ".join(f"`{f}`" for f in h.files)
        lines.append(f"| {h.label} | {files} | {h.n} | {h.uncertainty} | {h.baseline} | "
                     f"{'; '.join(h.reverses) or 'none in the results: ' + h.none_because} |")
    return lines


def recommendation(results: Path) -> str:
    """The README's first answer, in words: where the study's worker should be handed the box
    (the landscape's most central location of the paper score's minimum), and the frame."""
    stats = pd.read_csv(results / "landscape" / "stats.csv").set_index("score")
    best = stats.loc["paper_postural"]
    worker = pd.read_csv(results / "learning" / "targets.csv").set_index("target").loc[
        "paper", "worker"]
    x, y, z = (100 * float(best[f"best_{a}"]) for a in "xyz")
    side = "left" if x < 0 else "right"
    return (f"**What it recommends.** For the study's worker ({worker}: the 50th-percentile man "
            f"of the ANSUR II survey) taking the box in both hands: hand the box over with its "
            f"centre {y / 100:.2f} m above the floor, {z:.0f} cm in front of the point midway "
            f"between the worker's feet, centred ({abs(x):.1f} cm to the {side}), the most "
            f"central of the locations where the paper's score is lowest "
            f"({int(best['min'])}). Every location in this README, the report and every CSV, "
            f"flag and figure is in that worker's frame (the paper's Unity convention): origin "
            f"on the floor midway between the feet, x to the worker's right, y up, z forward, in "
            f"metres (angles in degrees, masses in kg), so this one is ({x / 100:.3f}, "
            f"{y / 100:.3f}, {z / 100:.3f}).")


def blocks(results: Path) -> dict[str, str]:
    return {"recommendation": recommendation(results),
            "headlines": "\n" + "\n".join(readme_table(results)) + "\n",
            "headline-rules": "\n" + "\n".join(report_table(results)) + "\n"}


def main() -> None:
    """Rewrite the README's headline table and the report's table of headlines."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
