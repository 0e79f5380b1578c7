"""The personalisation study's tables and answer in Markdown, from results/personalise/ only:
how many handovers each searcher needs to reach one worker's own optimum, and which one a
practitioner should use. make_tables.py puts the table into results/tables.md; the README and
docs/report.md carry the blocks and tests keep them equal; ``python personalise_tables.py``
rewrites the blocks."""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd
from readme_blocks import rewrite

from ergohandover.search.registry import SEARCHERS

NAMES = {"random-order": "random order", "prior": "the population prior alone",
         "bo": "Bayesian optimisation (GP)", "tpe": "TPE", "cmaes": "CMA-ES",
         "pso": "particle swarm", "qlearning": "the paper's tabular Q-learning",
         "randomwalk": "a random walk", "sac": "Soft Actor-Critic",
         "pairwise": "pairwise preferences (GP)", "fitted-twin": "the fitted twin",
         "no search": "no search (one handover at the prior's location)"}


def label(searcher: str) -> str:
    """A searcher's name in prose: ``Bayesian optimisation (GP) from the prior``."""
    base = SEARCHERS[searcher].variant_of if searcher in SEARCHERS else None
    return (NAMES.get(base, base) + " from the prior") if base else NAMES.get(searcher, searcher)


def _read(results: Path, name: str) -> pd.DataFrame:
    return pd.read_csv(results / "personalise" / name, keep_default_na=False, na_values=[""])


def evals(value: float, budget: int) -> str:
    """A median number of evaluations, or ``> budget`` where half the runs did not get there."""
    return f"> {budget:,}" if math.isnan(value) else f"{value:g}"


def ranking(summary: pd.DataFrame) -> pd.DataFrame:
    """Each searcher at its largest budget on the optimum: fewest median evaluations first
    (searchers that reach it in fewer than half their runs last, by success rate)."""
    optimum = summary[summary["target"] == "optimum"]
    last = optimum.loc[optimum.groupby("searcher", sort=False)["budget"].idxmax()]
    key = last["median_evals_to_optimum"].fillna(math.inf)
    return last.assign(_key=key, _rate=-last["success_rate"]).sort_values(
        ["_key", "_rate"], kind="stable").drop(columns=["_key", "_rate"])


def best_searcher(summary: pd.DataFrame) -> str:
    """The searcher that needs the fewest handovers with exact answers: the first of
    :func:`ranking`."""
    return str(ranking(summary).iloc[0]["searcher"])


def command_default(measured: pd.DataFrame) -> str:
    """``ergohandover personalise``'s default: of the ask/tell searchers told scores, the one
    whose recommendation (by its own rule) is most often a true optimum in model with postures
    measured with the headline's error, at the headline budget (then the lowest mean regret)."""
    rows = own_rule(measured)
    rows = rows[rows["searcher"].map(lambda s: s in SEARCHERS and SEARCHERS[s].kind == "searcher"
                                     and SEARCHERS[s].answers == "scores")]
    return str(best_measured(rows, "in-model", HEADLINE_ANSWERS, HEADLINE_BUDGET)["searcher"])


def summary_table(summary: pd.DataFrame) -> list[str]:
    budgets = sorted(summary["budget"].unique())
    head = " | ".join(f"optimum within {b:,}" for b in budgets)
    lines = [f"| searcher | {head} | median evaluations to the optimum | to within one "
             "point |",
             "|---|" + "---|" * len(budgets) + "---|---|"]
    for row in ranking(summary).itertuples():
        mine = summary[(summary["searcher"] == row.searcher) & (summary["target"] == "optimum")
                       ].set_index("budget")
        cells = [f"{mine.loc[b, 'success_rate']:.0%} ({mine.loc[b, 'ci_low']:.0%}–"
                 f"{mine.loc[b, 'ci_high']:.0%})" if b in mine.index else "not run"
                 for b in budgets]
        lines.append(f"| {label(row.searcher)} | {' | '.join(cells)} | "
                     f"{evals(row.median_evals_to_optimum, row.budget)} | "
                     f"{evals(row.median_evals_to_within_1, row.budget)} |")
    return lines


def answer(summary: pd.DataFrame) -> str:
    """The exact-answer comparison's answer: which searcher is fastest, how many handovers,
    against random order and the paper's Q-learning (the equal-budget comparison with answers
    as a site gets them says which to use)."""
    ranked = ranking(summary).set_index("searcher")
    best = ranked.index[0]
    first = ranked.iloc[0]
    workers, runs = int(first["n_workers"]), int(first["n_runs"])
    parts = [f"With exact answers (the ceiling), {label(best)} is the fastest: on {workers} "
             f"workers ({runs} runs) it reaches the worker's own optimum in a median of "
             f"{evals(first['median_evals_to_optimum'], first['budget'])} handovers and comes "
             f"within one point of it in "
             f"{evals(first['median_evals_to_within_1'], first['budget'])}"]
    mine = summary[(summary["searcher"] == best) & (summary["target"] == "optimum")
                   ].set_index("budget")
    within = [f"{mine.loc[b, 'success_rate']:.0%} of runs within {b}" for b in (10, 25, 50)
              if b in mine.index]
    if within:
        parts.append("it has found the optimum in " + ", ".join(within) + " handovers")
    for other in ("random-order", "qlearning"):
        if other in ranked.index and other != best:
            row = ranked.loc[other]
            parts.append(f"{label(other)} needs "
                         f"{evals(row['median_evals_to_optimum'], row['budget'])}")
    return "; ".join(parts) + "."


def ceiling(summary: pd.DataFrame) -> str:
    """The exact-answer comparison in a sentence: the best searcher's median handovers to a
    worker's own optimum beside random order's, the paper's learner's and Bayesian
    optimisation's."""
    ranked = ranking(summary).set_index("searcher")
    best, first = ranked.index[0], ranked.iloc[0]
    text = (f"{label(best)} reaches the worker's own optimum in a median of "
            f"{evals(first['median_evals_to_optimum'], first['budget'])} handovers")
    others = [f"{label(o)} {evals(row['median_evals_to_optimum'], row['budget'])}"
              for o in ("random-order", "qlearning", "bo+prior", "sac")
              if o in ranked.index and o != best for row in (ranked.loc[o],)]
    return text + (f" ({', '.join(others)})" if others else "")


HEADLINE_ANSWERS = "posture SD 5 deg"
"""The answers the headline quotes: the posture measured with the robustness part's 5° error."""
HEADLINE_BUDGET = 10
"""The handovers the headline quotes: a morning's handovers with one worker."""


def share(row) -> str:
    return f"{row['p_regret_0']:.0%} ({row['ci_low']:.0%}–{row['ci_high']:.0%})"


def rule_label(searcher: str, rule: str) -> str:
    said = {"lowest": ", its lowest reading", "confirm": ", measuring the best again",
            "model": "",
            "model, stopped": ", stopped by its model", "prior's location": ""}[rule]
    return label(searcher) + said


def best_measured(measured: pd.DataFrame, model: str, answers: str,
                  budget: int) -> pd.Series:
    """The searcher and rule whose recommendation is most often a true optimum (then the
    lowest mean regret) for one model, answer model and budget."""
    rows = measured[(measured["model"] == model) & (measured["answers"] == answers)
                    & (measured["budget"] == budget)]
    return rows.sort_values(["p_regret_0", "mean_regret"], ascending=[False, True],
                            kind="stable").iloc[0]


def at(measured: pd.DataFrame, model: str, answers: str, searcher: str, rule: str,
       budget: int) -> pd.Series:
    return measured[(measured["model"] == model) & (measured["answers"] == answers)
                    & (measured["searcher"] == searcher) & (measured["rule"] == rule)
                    & (measured["budget"] == budget)].iloc[0]


def own_rule(measured: pd.DataFrame) -> pd.DataFrame:
    """Each searcher's rows under its model's recommendation (its own model, or a model of
    its answers), without the alternatives (the lowest reading, ``confirm``, a model's stop)
    and the baseline."""
    return measured[measured["rule"] == "model"]


def gain(row) -> str:
    return (f"{row['gain']:+.2f} ({row['gain_ci_low']:+.2f} to {row['gain_ci_high']:+.2f}), "
            f"harm {row['harm']:.0%}")


def span(measured: pd.DataFrame, model: str, answers: str, budget: int,
         searchers: list[str]) -> tuple[float, float]:
    rows = own_rule(measured)
    rows = rows[(rows["model"] == model) & (rows["answers"] == answers)
                & (rows["budget"] == budget) & rows["searcher"].isin(searchers)]
    return float(rows["p_regret_0"].min()), float(rows["p_regret_0"].max())


def percent_span(low: float, high: float) -> str:
    return f"{low:.0%}" if round(100 * low) == round(100 * high) else \
        f"{100 * low:.0f}–{high:.0%}"


def headline(summary: pd.DataFrame, measured: pd.DataFrame | None = None) -> str:
    """The report's sentence: with answers as a site gets them, in model, at the headline
    budget, the best searcher's gain over no search with its interval and harm, how often it
    recommends the worker's true optimum beside no search, and out of model; the ceiling alone
    without measured answers."""
    if measured is None:
        first = ranking(summary).iloc[0]
        return f"on {int(first['n_workers'])} sampled workers, {ceiling(summary)}"
    inside = own_rule(measured[measured["searcher"] != "random-order"])
    best = best_measured(inside, "in-model", HEADLINE_ANSWERS, HEADLINE_BUDGET)
    nothing = at(measured, "in-model", HEADLINE_ANSWERS, "no search", "prior's location", 1)
    out = at(measured, "out-of-model", HEADLINE_ANSWERS, best["searcher"], best["rule"],
             HEADLINE_BUDGET)
    out_nothing = at(measured, "out-of-model", HEADLINE_ANSWERS, "no search",
                     "prior's location", 1)
    runs = int(best["n_runs"]) // int(best["n_workers"])
    text = (f"answered as a site would — each handover's posture measured with 5° of error — "
            f"after {HEADLINE_BUDGET} handovers {label(best['searcher'])} gains "
            f"{gain(best)} points of true regret over handing over once at the prior's "
            f"location (N = {int(best['n_workers'])} workers, {runs} runs each) and recommends "
            f"a worker's true optimum in {share(best)} of runs against no search's "
            f"{share(nothing)}; for {int(out['n_workers'])} workers whose twin differs from "
            f"the prior's, {share(out)} against {out_nothing['p_regret_0']:.0%}")
    for model in unknown_models(measured):
        there = at(measured, model, HEADLINE_ANSWERS, best["searcher"], best["rule"],
                   HEADLINE_BUDGET)
        alone = at(measured, model, HEADLINE_ANSWERS, "no search", "prior's location", 1)
        text += (f"; for {int(there['n_workers'])} {UNKNOWN_SAID.get(model, model)}, it gains "
                 f"{gain(there)} and finds the optimum in {share(there)} against "
                 f"{alone['p_regret_0']:.0%}")
    imu = [a for a in measured["answers"].unique() if a.startswith("IMU")]
    if imu:
        there = at(measured, "in-model", imu[0], best["searcher"], best["rule"],
                   HEADLINE_BUDGET)
        text += (f"; with an IMU suit's errors ({int(there['n_runs']) // int(there['n_workers'])}"
                 f" run each), {share(there)}, gain {gain(there)}")
    return text


UNKNOWN_SAID = {"impaired": "impaired workers (a shoulder, elbow or wrist of restricted range)",
                "steps or other proportions": "workers who step toward the box or are of "
                                              "fixed-ratio proportions"}
"""How the sentences name the groups of workers the prior does not know."""


def unknown_models(measured: pd.DataFrame) -> list[str]:
    """The groups of workers the prior does not know that the results hold."""
    return [m for m in dict.fromkeys(measured["model"]) if m not in ("in-model", "out-of-model")]


def other_reversals(measured: pd.DataFrame, best: pd.Series) -> list[str]:
    """Where the best searcher's gain over no search has an interval reaching 0 at the
    headline budget among workers the prior does not know (under the headline's answers) and
    in model with an IMU's errors."""
    found = []
    for model, said in [(m, HEADLINE_ANSWERS) for m in unknown_models(measured)] + [
            ("in-model", a) for a in measured["answers"].unique() if a.startswith("IMU")]:
        there = at(measured, model, said, best["searcher"], best["rule"], HEADLINE_BUDGET)
        if there["gain_ci_low"] <= 0:
            found.append(f"{model} workers, {said}: the gain's interval reaches "
                         f"{bound(there['gain_ci_low'])}")
    return found


def bound(value: float) -> str:
    """An interval's end in points: two decimals, three where two would round a value that is
    not zero to 0.00 (a bound just below zero is below zero)."""
    return f"{value:+.3f}" if 0 < abs(value) < 0.005 else f"{value:+.2f}"


def measured_table(measured: pd.DataFrame) -> list[str]:
    """Per model, searcher and rule: the share of runs whose recommendation after the headline
    budget is a true optimum (95 % interval over workers) under each answer model; no
    search's first."""
    answers = list(dict.fromkeys(measured["answers"]))
    lines = [f"| workers | searcher | {' | '.join(answers)} |",
             "|---|---|" + "---|" * len(answers)]
    rows = measured[measured["budget"].isin((1, HEADLINE_BUDGET))].sort_values(
        "model", kind="stable", key=lambda c: c != "in-model")
    for (model, searcher, rule), table in rows.groupby(["model", "searcher", "rule"],
                                                        sort=False):
        found = table.set_index("answers")
        cells = [share(found.loc[a]) if a in found.index else "not run" for a in answers]
        lines.append(f"| {model} ({int(table['n_workers'].iloc[0])}) | "
                     f"{rule_label(searcher, rule)} | {' | '.join(cells)} |")
    return lines


def measured_budgets(measured: pd.DataFrame, answers: str = HEADLINE_ANSWERS) -> list[str]:
    """In model, under one answer model: the share at a true optimum after each budget, and
    the gain over no search with its harm at the headline budget, per searcher and rule (no
    search's first)."""
    rows = measured[(measured["model"] == "in-model") & (measured["answers"] == answers)]
    budgets = sorted(b for b in rows["budget"].unique() if b > 1)
    head = " | ".join(f"after {b}" for b in budgets)
    lines = [f"| searcher | a true optimum {head} | gain over no search after "
             f"{HEADLINE_BUDGET} [points], harm | handovers used |",
             "|---|" + "---|" * len(budgets) + "---|---|"]
    for (searcher, rule), table in rows.groupby(["searcher", "rule"], sort=False):
        found = table.set_index("budget")
        if searcher == "no search":
            lines.append(f"| {label(searcher)} | {share(found.loc[1])} (one handover) | "
                         + " | ".join("" for _ in budgets[1:]) + " | — | 1 |")
            continue
        cells = [share(found.loc[b]) if b in found.index else "not run" for b in budgets]
        last = found.loc[HEADLINE_BUDGET]
        lines.append(f"| {rule_label(searcher, rule)} | {' | '.join(cells)} | {gain(last)} | "
                     f"{last['mean_handovers']:.1f} |")
    return lines


def model_or_lowest(measured: pd.DataFrame) -> str:
    """For the searchers without a model of their own, in model at the headline budget, under
    the headline's answers and an IMU's: how often a model of the worker fitted to their
    answers recommends a true optimum, beside their lowest single reading."""
    said = []
    for answers, words in ((HEADLINE_ANSWERS, f"postures measured with "
                            f"{HEADLINE_ANSWERS.split()[2]}° of error"),
                           ("IMU", "an IMU's errors")):
        rows = measured[(measured["model"] == "in-model") & (measured["answers"] == answers)
                        & (measured["budget"] == HEADLINE_BUDGET)]
        pairs = []
        for searcher, table in rows.groupby("searcher", sort=False):
            found = table.set_index("rule")
            if {"model", "lowest"} <= set(found.index):
                pairs.append(f"{label(searcher)} {share(found.loc['model'])} against "
                             f"{found.loc['lowest', 'p_regret_0']:.0%}")
        if pairs:
            n, runs = int(rows["n_workers"].max()), int(rows["n_runs"].max())
            said.append(f"with {words} ({n} workers, {runs // n} run(s) each): "
                        + "; ".join(pairs))
    return (f"\nIn model, after {HEADLINE_BUDGET} handovers, a true optimum is recommended by "
            "the model of the worker against the lowest single reading, " + "; and ".join(said)
            + ".\n")


def blocks(results: Path) -> dict[str, str]:
    """Each generated block's text, from ``results``/personalise/ only."""
    summary = _read(results, "summary.csv")
    measured = (_read(results, "measured_summary.csv")
                if (results / "personalise" / "measured_summary.csv").is_file() else None)
    found = {"personalise-headline": headline(summary, measured),
             "personalise-answer": answer(summary),
             "personalise-table": "\n" + "\n".join(summary_table(summary)) + "\n"}
    if measured is not None:
        found["personalise-measured"] = "\n" + "\n".join(measured_table(measured)) + "\n"
        found["personalise-measured-budgets"] = ("\n" + "\n".join(measured_budgets(measured))
                                                 + "\n")
        found["personalise-model-or-lowest"] = model_or_lowest(measured)
    return found


def section(results: Path) -> list[str]:
    """results/tables.md's section."""
    summary = _read(results, "summary.csv")
    return ["## Personalisation: handovers to one worker's own optimum", "",
            answer(summary), "", *summary_table(summary), ""]


def main() -> None:
    """Rewrite the personalisation blocks from results/ wherever each lives."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
