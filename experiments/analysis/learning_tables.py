"""The learning study's tables in Markdown, from results/learning/ only: each target, the
verdicts (does a learner beat the random walk and random draws, run for run, at the
paper-rate budgets and under each mapping?), every agent's success rate, the tests' power and
the greedy rollouts. make_tables.py puts them into results/tables.md; docs/report.md carries
the verdicts (README.md the headline claim) and a test keeps them equal."""

from __future__ import annotations

import math

import pandas as pd
from readme_blocks import rewrite

from ergohandover.search.registry import SEARCHERS

AGENT_NAMES = {name: entry.label for name, entry in SEARCHERS.items()}
PAPER_RATE = 315.0
"""The paper's evaluations per second (the study's ``LearningConfig.PAPER_RATE``): the
``mapping`` of the budgets ``paper-2min`` and ``paper-5min``."""


def rate(successes: int, n: int, low: float, high: float) -> str:
    """``7/10 (0.40–0.89)``: successes of n with the 95 % Wilson interval."""
    return f"{int(successes)}/{int(n)} ({low:.2f}–{high:.2f})"


def evaluations(value: float) -> str:
    """A median of evaluations, or ``>budget`` when more than half the runs never got there."""
    return "> budget" if not math.isfinite(value) else f"{value:,.0f}"


def p_text(p: float) -> str:
    """``p = 0.031`` in two significant digits, ``p < 1e-10`` below that."""
    return "p < 1e-10" if p < 1e-10 else f"p = {p:.2g}"


def targets_table(targets: pd.DataFrame) -> list[str]:
    lines = ["| target | objective (goal) | worker, gaze | grid | optimum | target cells "
             "(share of grid) |", "|---|---|---|---|---|---|"]
    for t in targets.itertuples():
        lines.append(f"| {t.target} | {t.objective} ({t.goal}) | {t.worker}, gaze {t.gaze} | "
                     f"{t.grid_cells:,} cells every {grid_step(t.grid)} | {t.score:g} | "
                     f"{t.cells:,} ({t.fraction:.4%}) |")
    return lines


def grid_step(text: str) -> str:
    """``20 mm in 'paper-code'`` from a grid's description."""
    return text.split("every ")[1].replace("in boundary ", "in ")


def paper_budgets(summary: pd.DataFrame) -> list[str]:
    """The budgets at the paper's rate (315 evaluations/s), fewest evaluations first."""
    at = summary[summary["mapping"] == PAPER_RATE].sort_values("steps", kind="stable")
    return list(dict.fromkeys(at["budget"]))


def step_budgets(summary: pd.DataFrame) -> list[str]:
    """Every step budget, fewest evaluations first."""
    at = summary.dropna(subset=["steps"]).sort_values("steps", kind="stable")
    return list(dict.fromkeys(at["budget"]))


def verdict_table(summary: pd.DataFrame, comparisons: pd.DataFrame, budgets: list[str],
                  learner: str = "qlearning") -> list[str]:
    """Per target and budget: the learner's, the random walk's and random draws' success
    with intervals, and the learner against each run for run (Wilcoxon signed-rank on
    evaluations to the target with censored runs last, Holm-corrected over every comparison;
    r > 0: the learner sooner)."""
    cells = summary.set_index(["target", "agent", "budget"])
    lines = [f"| target | budget | {AGENT_NAMES[learner]} | random walk | random draws | "
             f"{AGENT_NAMES[learner]} vs random walk | vs random draws |",
             "|---|---|---|---|---|---|---|"]
    for (target, budget), group in comparisons[(comparisons["agent"] == learner)
                                              & comparisons["budget"].isin(budgets)].groupby(
            ["target", "budget"], sort=False):
        shown = [rate(*cells.loc[(target, a, budget), ["successes", "n_runs", "ci_low",
                                                       "ci_high"]])
                 for a in (learner, "randomwalk", "random-draws")]
        tests = []
        for reference in ("randomwalk", "random-draws"):
            row = group[group["versus"] == reference].iloc[0]
            shown = verdicts(group[group["versus"] == reference]).iloc[0]
            shown = "both at the ceiling" if shown == CEILING else shown
            tests.append(f"{shown} ({p_text(row['p_wilcoxon_holm'])}, "
                         f"r = {row['rank_biserial']:+.2f})")
        lines.append(f"| {target} | {budget} | {' | '.join(shown)} | {' | '.join(tests)} |")
    return lines


SHORT = {"better": "better", "worse": "worse", "no conclusion": "–"}
CEILING = "ceiling"
"""The verdict shown where both agents succeed in all but at most one run: an equivalence test
passes there whether or not the agents search alike, so it is not reported as equivalence."""


def at_ceiling(rows: pd.DataFrame) -> pd.Series:
    """Comparisons where both agents reached the target in at least n - 1 of the n runs."""
    return (rows["successes_agent"] >= rows["n"] - 1) & (rows["successes_versus"] >= rows["n"] - 1)


def verdicts(rows: pd.DataFrame) -> pd.Series:
    """Each comparison's verdict as the tables show it: ``ceiling`` where both agents are at
    the ceiling and no difference was found, else the study's verdict."""
    shown = rows["verdict"].copy()
    tie = at_ceiling(rows) & ~rows["verdict"].isin(("better", "worse"))
    shown[tie] = CEILING
    return shown


def short_verdict(text: str) -> str:
    """A verdict in a narrow cell: ``≡`` for equivalent success rates, ``–`` for none."""
    if text == CEILING:
        return CEILING
    return "≡" if text.startswith("equivalent") else SHORT[text]


def mapping_table(comparisons: pd.DataFrame, budgets: list[str],
                  learner: str = "qlearning") -> list[str]:
    """The learner against the random walk / random draws at every budget of every
    mapping, one row per target."""
    at = comparisons[comparisons["agent"] == learner]
    at = at.assign(verdict=verdicts(at)).set_index(["target", "budget", "versus"])
    lines = ["| target | " + " | ".join(budgets) + " |", "|---|" + "---|" * len(budgets)]
    for target in dict.fromkeys(comparisons["target"]):
        cells = []
        for budget in budgets:
            pair = [short_verdict(at.loc[(target, budget, v), "verdict"])
                    if (target, budget, v) in at.index else "·"
                    for v in ("randomwalk", "random-draws")]
            cells.append(" / ".join(pair))
        lines.append(f"| {target} | " + " | ".join(cells) + " |")
    return lines


def per_agent(at: pd.DataFrame, target: str, agents: list[str], cell) -> str:
    """One target's cells, ``cell(row)`` for each agent (``–`` where it has no row), joined."""
    return " | ".join(cell(at.loc[(target, a)]) if (target, a) in at.index else "–"
                      for a in agents)


def agents_table(summary: pd.DataFrame, budget: str) -> list[str]:
    """Every agent's success (with interval) and median evaluations to the target, per target,
    at one budget."""
    agents = [a for a in AGENT_NAMES if a in set(summary["agent"])]
    lines = ["| target | " + " | ".join(AGENT_NAMES[a] for a in agents) + " |",
             "|---|" + "---|" * len(agents)]
    at = summary[summary["budget"] == budget].set_index(["target", "agent"])

    def cell(r) -> str:
        return (f"{int(r['successes'])}/{int(r['n_runs'])}, "
                f"{evaluations(r['median_evals_to_target'])}")

    for target in dict.fromkeys(summary["target"]):
        lines.append(f"| {target} | {per_agent(at, target, agents, cell)} |")
    return lines


def rollouts_table(summary: pd.DataFrame) -> list[str]:
    """Greedy rollouts of each learner's final policy beside the random walk from the same
    starts: walks that reached the target within the grid's Manhattan diameter."""
    walks = summary.dropna(subset=["rollouts"])
    agents = [a for a in ("qlearning", "qlearning-adaptive", "dqn", "randomwalk")
              if a in set(walks["agent"])]
    lines = ["| target | steps allowed | " + " | ".join(AGENT_NAMES[a] for a in agents) + " |",
             "|---|---|" + "---|" * len(agents)]
    at = walks.set_index(["target", "agent"])

    def cell(r) -> str:
        steps = "" if not math.isfinite(r["rollout_mean_steps"]) else \
            f", {r['rollout_mean_steps']:.0f} steps"
        return (f"{int(r['rollout_reached'])}/{int(r['rollouts'])} "
                f"({r['rollout_ci_low']:.2f}–{r['rollout_ci_high']:.2f}){steps}")

    for target in dict.fromkeys(walks["target"]):
        limit = int(at.loc[(target, agents[0]), "rollout_limit"])
        lines.append(f"| {target} | {limit} | {per_agent(at, target, agents, cell)} |")
    return lines


def power_table(power: pd.DataFrame) -> list[str]:
    """Each test's power at each number of paired runs, for one comparison at α and at Holm's
    first step (α / the number of comparisons)."""
    first = power.iloc[0]
    levels = list(dict.fromkeys(power["level"]))
    heads = [f"{level} (α = {power.loc[power['level'] == level, 'alpha'].iloc[0]:.2g})"
             for level in levels]
    lines = ["| runs | test | effect | " + " | ".join(heads) + " |",
             "|---|---|---|" + "---|" * len(levels)]
    for (agents, n, test, effect), group in power.groupby(["agents", "n", "test", "effect"],
                                                          sort=False):
        values = group.set_index("level")["power"]
        lines.append(f"| {int(n)} ({agents}) | {test} | {effect} | "
                     + " | ".join(f"{values[level]:.2f}" for level in levels) + " |")
    lines.append("")
    lines.append(f"Holm's first step divides α = {first['alpha']:g} by the "
                 f"{int(first['family'])} comparisons of comparisons.csv; the equivalence "
                 f"margin is ±{100 * first['margin']:g} percentage points of success rate.")
    return lines


BLOCKS = ("learning-claim", "learning-targets", "learning-tally", "learning-verdicts",
          "learning-mappings", "learning-power", "learning-rollouts")
"""The generated blocks, each between ``<!-- name -->`` and ``<!-- /name -->`` in README.md or
docs/report.md."""


def blocks(results) -> dict[str, str]:
    """Each generated block's text, from ``results``/learning/ only."""
    folder = results / "learning"
    read = lambda name: pd.read_csv(folder / name, keep_default_na=False,  # noqa: E731
                                    na_values=[""])
    summary, comparisons, targets, power = (read(n) for n in (
        "summary.csv", "comparisons.csv", "targets.csv", "power.csv"))
    paper = paper_budgets(summary)
    table = lambda lines: "\n" + "\n".join(lines) + "\n"  # noqa: E731
    return {"learning-claim": claim(summary, paper),
            "learning-learns": learns(comparisons, power),
            "learning-targets": table(targets_table(targets)),
            "learning-tally": table(tally(comparisons)),
            "learning-verdicts": table(verdict_table(summary, comparisons, paper)),
            "learning-mappings": table(mapping_table(comparisons, step_budgets(summary))),
            "learning-power": table(power_table(power)),
            "learning-rollouts": table(rollouts_table(summary))}


def claim(summary: pd.DataFrame, budgets: list[str], target: str = "paper") -> str:
    """The headline table's answer to the paper's claim that every run reaches the minimum."""
    at = summary[summary["target"] == target].set_index(["agent", "budget"])
    counts = {a: " and ".join(rate(*at.loc[(a, b), ["successes", "n_runs", "ci_low",
                                                     "ci_high"]]) for b in budgets)
              for a in ("qlearning", "randomwalk", "random-draws")}
    steps = " and ".join(f"{int(at.loc[('qlearning', b), 'steps']):,}" for b in budgets)
    score = at["target_score"].iloc[0]
    return (f"at budgets matched to the paper's caps ({steps} evaluations) Q-learning reaches "
            f"the minimum ({score:g}) in {counts['qlearning']} runs, a random walk in "
            f"{counts['randomwalk']}, random draws in {counts['random-draws']} (95 % Wilson "
            "intervals); rarer targets tell them apart: the learning study")


def learns(comparisons: pd.DataFrame, power: pd.DataFrame) -> str:
    """The headline table's answer to "does it learn?": each learner's verdicts against the
    random walk and random draws over every target and budget (Holm-corrected), the ceiling
    counted apart, and what the equivalence test could have found at the study's runs."""
    def counted(agent: str, versus: str) -> tuple[int, dict]:
        rows = comparisons[(comparisons["agent"] == agent) & (comparisons["versus"] == versus)]
        return len(rows), verdicts(rows).map(short_verdict).value_counts().to_dict()

    q = comparisons[comparisons["agent"] == "qlearning"]
    n_walk, walk = counted("qlearning", "randomwalk")
    n_random, random = counted("qlearning", "random-draws")
    pairs = q[q["versus"] == "randomwalk"]
    open_ = pairs[verdicts(pairs) == "no conclusion"]
    raw = min(open_["p_wilcoxon"].min(), open_["p_mcnemar"].min()) if len(open_) else 1.0
    margin = 100 * q["margin"].iloc[0]
    tost = power[(power["test"] == "TOST") & (power["level"] == "Holm's first step")
                 & (power["n"] == int(q["n"].min()))
                 & power["effect"].str.contains("1 % of runs discordant")].iloc[0]
    text = (f"over {q['target'].nunique()} targets and {q['budget'].nunique()} budgets (the "
            f"paper's two caps at {q['mapping'].nunique()} rates, "
            f"{int(q['n'].min())} paired runs each, Holm-corrected), tabular Q-learning beats "
            f"a random walk in {walk.get('better', 0)} of {n_walk} comparisons (worse in "
            f"{walk.get('worse', 0)}; no conclusion in {walk.get('–', 0)}, "
            + ("none with an unadjusted p below 0.05" if raw >= 0.05 else
               f"the smallest unadjusted p {raw:.2g}")
            + f"; in {walk.get(CEILING, 0)} both reach the target in all but at most one run, "
            f"a ceiling that tells nothing apart"
            + (f"; equivalent within ±{margin:g} points of success rate in {walk['≡']}"
               if walk.get("≡") else "")
            + f") and random draws in {random.get('better', 0)} of {n_random} (worse in "
            f"{random.get('worse', 0)}); equal learners would pass the equivalence test "
            f"(±{margin:g} points) in only {100 * tost['power']:.0f} % of comparisons at Holm's "
            f"first step with 1 % of runs discordant each way")
    if (comparisons["agent"] == "dqn").any():
        n_dqn, dqn = counted("dqn", "randomwalk")
        n_dqn_random, dqn_random = counted("dqn", "random-draws")
        runs = int(comparisons.loc[comparisons["agent"] == "dqn", "n"].min())
        text += (f"; DQN ({runs} runs) beats the walk in {dqn.get('better', 0)} of {n_dqn} and "
                 f"random draws in {dqn_random.get('better', 0)} of {n_dqn_random}")
    return text


def tally(comparisons: pd.DataFrame) -> list[str]:
    """How often each learner is better, worse, equivalent in success rate or neither against
    each reference agent, over every target, per mapping (Holm-corrected, α as configured)."""
    lines = []
    agents = list(dict.fromkeys(comparisons["agent"]))
    groups = sorted(comparisons.groupby(["agent", "mapping"], sort=False, dropna=False),
                    key=lambda item: (agents.index(item[0][0]), item[0][1]))
    for (agent, mapping), group in groups:
        parts = []
        for reference, g in group.groupby("versus", sort=False):
            counts = verdicts(g).map(short_verdict).value_counts()
            parts.append(f"against {AGENT_NAMES[reference]} better in "
                         f"{counts.get('better', 0)}, worse in {counts.get('worse', 0)}, "
                         f"both at the ceiling in {counts.get(CEILING, 0)}, equivalent in "
                         f"success in {counts.get('≡', 0)}, no conclusion in "
                         f"{counts.get('–', 0)}")
        pairs = group[["target", "budget"]].drop_duplicates()
        where = "wall-clock caps" if math.isnan(mapping) else f"{mapping:g} evaluations/s"
        lines.append(f"- {AGENT_NAMES[agent]} at {where}, {len(pairs)} "
                     f"comparisons ({pairs['target'].nunique()} targets × "
                     f"{pairs['budget'].nunique()} budgets): " + "; ".join(parts) + ".")
    return lines


def main() -> None:
    """Rewrite the learning blocks from results/ wherever each lives, README.md or
    docs/report.md (run after the study)."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
