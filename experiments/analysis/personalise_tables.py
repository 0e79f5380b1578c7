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
         "randomwalk": "a random walk", "sac": "Soft Actor-Critic"}


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
    """The searcher a practitioner should use: the first of :func:`ranking`."""
    return str(ranking(summary).iloc[0]["searcher"])


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
    """The plain answer: which searcher, how many handovers, against random order and the
    paper's Q-learning."""
    ranked = ranking(summary).set_index("searcher")
    best = ranked.index[0]
    first = ranked.iloc[0]
    workers, runs = int(first["n_workers"]), int(first["n_runs"])
    parts = [f"Use {label(best)}: on {workers} workers ({runs} runs) it reaches the worker's own "
             f"optimum in a median of {evals(first['median_evals_to_optimum'], first['budget'])}"
             f" handovers and comes within one point of it in "
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


def headline(summary: pd.DataFrame) -> str:
    """The README's row: the best searcher's median handovers to a worker's own optimum beside
    random order's, the paper's learner's and Bayesian optimisation's."""
    ranked = ranking(summary).set_index("searcher")
    best, first = ranked.index[0], ranked.iloc[0]
    text = (f"on {int(first['n_workers'])} sampled workers, {label(best)} reaches the "
            f"worker's own optimum in a median of "
            f"{evals(first['median_evals_to_optimum'], first['budget'])} handovers")
    others = [f"{label(o)} {evals(row['median_evals_to_optimum'], row['budget'])}"
              for o in ("random-order", "qlearning", "bo+prior", "sac")
              if o in ranked.index and o != best for row in (ranked.loc[o],)]
    return text + (f" ({', '.join(others)})" if others else "")


def measured_table(measured: pd.DataFrame) -> list[str]:
    """Per searcher and error SD: the share of runs whose recommendation is a true optimum
    after each budget (95 % interval over workers), and the mean true regret at the largest."""
    budgets = sorted(measured["budget"].unique())
    largest = budgets[-1]
    head = " | ".join(f"after {b}" for b in budgets)
    lines = [f"| searcher | error SD | recommendation a true optimum {head} | mean true "
             f"regret after {largest} [points] |",
             "|---|---|" + "---|" * len(budgets) + "---|"]
    for (searcher, sd), table in measured.groupby(["searcher", "sd_deg"], sort=False):
        rows = table.set_index("budget")
        cells = [f"{rows.loc[b, 'p_regret_0']:.0%} ({rows.loc[b, 'ci_low']:.0%}–"
                 f"{rows.loc[b, 'ci_high']:.0%})" for b in budgets]
        last = rows.loc[largest]
        lines.append(f"| {label(searcher)} | {sd:g}° | {' | '.join(cells)} | "
                     f"{last['mean_regret']:.2f} ({last['regret_ci_low']:.2f}–"
                     f"{last['regret_ci_high']:.2f}) |")
    first = measured.iloc[0]
    lines += ["", f"{int(first['n_workers'])} workers, {int(first['n_runs'])} runs per "
              "searcher, error SD and budget."]
    return lines


def blocks(results: Path) -> dict[str, str]:
    """Each generated block's text, from ``results``/personalise/ only."""
    summary = _read(results, "summary.csv")
    found = {"personalise-headline": headline(summary),
             "personalise-answer": answer(summary),
             "personalise-table": "\n" + "\n".join(summary_table(summary)) + "\n"}
    if (results / "personalise" / "measured_summary.csv").is_file():
        measured = _read(results, "measured_summary.csv")
        found["personalise-measured"] = "\n" + "\n".join(measured_table(measured)) + "\n"
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
