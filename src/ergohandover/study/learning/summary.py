"""What the learning study's runs say: per cell (target, agent, budget) the success rate with
its Wilson interval and the evaluations to the target; each learner against the random walk and
random sampling, run for run, with Holm's correction over every comparison, an equivalence test
and a verdict; the tests' power at the study's numbers of runs; best-so-far and success curves
with bootstrap bands; the location each agent keeps."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...landscape.stats import most_symmetric
from ...search.statistics import (
    best_so_far,
    bootstrap_band,
    censored_median,
    cliffs_delta,
    holm,
    mcnemar_power,
    paired_comparison,
    signed_rank_power,
    tost_power,
    verdict,
    wilson,
)

CELL = ["target", "agent", "budget"]
REFERENCES = ("randomwalk", "random-draws")
"""What every learner is compared with: the same moves without learning, and plain sampling."""
CURVE_POINTS = 40


def summary(runs: pd.DataFrame, full: pd.DataFrame) -> pd.DataFrame:
    """One row per (target, agent, budget), in the runs' order; the greedy rollouts of the full
    runs beside the budget they ran to."""
    rows = []
    for (target, agent, budget), cell in runs.groupby(CELL, sort=False):
        successes, n = int(cell["reached"].sum()), len(cell)
        low, high = wilson(successes, n)
        evaluations = cell["evaluations_to_target"].to_numpy(dtype=float)
        first = cell.iloc[0]
        rows.append({
            "target": target, "agent": agent, "budget": budget, "mapping": first["mapping"],
            "cap_min": first["cap_min"], "steps": first["steps"],
            "time_cap_s": first["time_cap_s"], "n_runs": n, "successes": successes,
            "success_rate": successes / n, "ci_low": low, "ci_high": high,
            "median_evals_to_target": censored_median(evaluations),
            "censored": n - successes, "median_best_score": cell["best_score"].median(),
            "worst_best_score": cell["best_score"].max(),
            "target_score": first["target_score"],
            "median_evaluations": cell["evaluations"].median(),
            "median_steps_per_s": cell["steps_per_s"].median()})
    table = pd.DataFrame(rows)
    walks = rollout_summary(full)
    if walks.empty or table.empty:
        return table
    return table.merge(walks, on=CELL, how="left")


def rollout_summary(full: pd.DataFrame) -> pd.DataFrame:
    """Per (target, agent, budget) of the full runs that were rolled out: walks that reached
    the target, with a Wilson interval, and their mean steps."""
    if "rollouts" not in full:
        return pd.DataFrame()
    rows = []
    for (target, agent, budget), walks in full[full["rollouts"] > 0].groupby(CELL, sort=False):
        reached, total = int(walks["rollout_reached"].sum()), int(walks["rollouts"].sum())
        low, high = wilson(reached, total)
        rows.append({"target": target, "agent": agent, "budget": budget,
                     "rollout_runs": len(walks), "rollouts": total,
                     "rollout_limit": int(walks["rollout_limit"].iloc[0]),
                     "rollout_reached": reached, "rollout_rate": reached / total,
                     "rollout_ci_low": low, "rollout_ci_high": high,
                     "rollout_mean_steps": walks["rollout_mean_steps"].mean()})
    return pd.DataFrame(rows)


COMPARISON_COLUMNS = (
    "target", "budget", "mapping", "cap_min", "agent", "versus", "n", "successes_agent",
    "successes_versus", "success_diff", "median_agent", "median_versus", "p_wilcoxon",
    "p_wilcoxon_holm", "rank_biserial", "cliffs_delta", "p_mcnemar", "p_mcnemar_holm", "margin",
    "p_tost", "p_tost_holm", "verdict")


def comparisons(runs: pd.DataFrame, learners: tuple[str, ...], margin: float,
                alpha: float) -> pd.DataFrame:
    """Each learner against each reference agent, per target and budget, run for run (the
    runs both have: DQN's first ``dqn_runs``). Where no reference agent ran (the paper's own
    protocol: Q-learning and DQN), the first learner is compared with each other learner.

    Holm's correction runs over every row of the table (the whole family), separately for
    each test; the verdict follows the corrected signed-rank test, then the corrected TOST
    (:func:`~...search.statistics.verdict`)."""
    references = [r for r in REFERENCES if r in set(runs["agent"])]
    if not references:
        learners, references = learners[:1], list(learners[1:])
    rows = []
    for (target, budget), group in runs.groupby(["target", "budget"], sort=False):
        by_agent = {a: g.set_index("run")["evaluations_to_target"].astype(float)
                    for a, g in group.groupby("agent")}
        size = group["steps"].iloc[0]
        size = group["evaluations"].max() if pd.isna(size) else size  # a wall-clock cap
        for learner in learners:
            for reference in references:
                if learner not in by_agent or reference not in by_agent:
                    continue
                both = by_agent[learner].index.intersection(by_agent[reference].index)
                a = by_agent[learner].loc[both].to_numpy()
                b = by_agent[reference].loc[both].to_numpy()
                test = paired_comparison(a, b, size, margin)
                hits_a, hits_b = int((~np.isnan(a)).sum()), int((~np.isnan(b)).sum())
                rows.append({"target": target, "budget": budget,
                             "mapping": group["mapping"].iloc[0],
                             "cap_min": group["cap_min"].iloc[0], "agent": learner,
                             "versus": reference, "successes_agent": hits_a,
                             "successes_versus": hits_b,
                             "success_diff": (hits_a - hits_b) / max(1, len(both)),
                             "median_agent": censored_median(a),
                             "median_versus": censored_median(b), **test,
                             "cliffs_delta": cliffs_delta(a, b), "margin": margin})
    table = pd.DataFrame(rows, columns=[c for c in COMPARISON_COLUMNS
                                        if not c.endswith("_holm") and c != "verdict"])
    for test in ("p_wilcoxon", "p_mcnemar", "p_tost"):
        table[f"{test}_holm"] = holm(table[test])
    table["verdict"] = [verdict(r.p_wilcoxon_holm, r.rank_biserial, r.p_tost_holm, margin,
                                alpha) for r in table.itertuples()]
    return table[list(COMPARISON_COLUMNS)]


POWER_EFFECTS = (
    ("signed-rank", "paired shift d_z = 0.3", 0.3, None),
    ("signed-rank", "paired shift d_z = 0.5", 0.5, None),
    ("McNemar", "success 10 pp apart (15 % vs 5 % of runs discordant)", 0.15, 0.05),
    ("McNemar", "success 20 pp apart (25 % vs 5 % of runs discordant)", 0.25, 0.05),
    ("TOST", "equal success, every run concordant", 0.0, None),
    ("TOST", "equal success, 1 % of runs discordant each way", 0.01, None),
    ("TOST", "equal success, 3 % of runs discordant each way", 0.03, None))
"""The effects at which power.csv states each test's power: a small-to-medium and a medium
shift in evaluations to the target (Cohen's d_z of the paired differences), success rates 10
and 20 points apart, and equal success rates with few discordant runs (where the study's
agents mostly are, near 0 or 100 % success)."""


def power(sizes: dict[str, int], family: int, margin: float, alpha: float) -> pd.DataFrame:
    """power.csv: each test's power at each number of paired runs in ``sizes`` (a label, e.g.
    the agents that have that many, to n), at ``alpha`` for one comparison and at Holm's first
    step, alpha / ``family`` (the strictest threshold a comparison of the family meets)."""
    rows = []
    for label, n in sizes.items():
        for level, a in (("one comparison", alpha), ("Holm's first step", alpha / family)):
            for test, effect, x, y in POWER_EFFECTS:
                if test == "signed-rank":
                    value = signed_rank_power(n, x, a)
                elif test == "McNemar":
                    value = mcnemar_power(n, x, y, a)
                else:
                    value = tost_power(n, x, margin, a)
                rows.append({"agents": label, "n": n, "test": test, "effect": effect,
                             "level": level, "alpha": a, "family": family, "margin": margin,
                             "power": value})
    return pd.DataFrame(rows)


CURVE_COLUMNS = ("target", "agent", "budget", "evaluations", "reached_share", "reached_low",
                 "reached_high", "mean_best", "best_low", "best_high")


def curves(searches: pd.DataFrame, traces: pd.DataFrame, seed: int) -> pd.DataFrame:
    """Per (target, agent) of the search runs (one row per run, at its own budget), at
    log-spaced evaluation counts up to that budget: the share of runs that have reached the
    target and the mean best score so far, each with a 95 % bootstrap band. Every smaller step
    budget is a point of the curve; runs that stop at a wall clock share no evaluation axis."""
    if searches.empty:
        return pd.DataFrame(columns=CURVE_COLUMNS)
    rng = np.random.default_rng(seed)
    frames = []
    by_run = {key: t for key, t in traces.groupby([*CELL, "run"], sort=False)}
    for (target, agent, budget), cell in searches.groupby(CELL, sort=False):
        steps = int(cell["steps"].iloc[0])
        at = np.unique(np.geomspace(1, steps, CURVE_POINTS).round().astype(int))
        reached = (cell["evaluations_to_target"].to_numpy(dtype=float)[:, None]
                   <= at[None, :]).astype(float)
        best = np.array([best_so_far(t["step"].to_numpy(), t["best_score"].to_numpy(), at)
                         for t in (by_run[(target, agent, budget, r)] for r in cell["run"])])
        # Before a run's first feasible cell its best is undefined: the worst it later had.
        best = np.where(np.isinf(best), np.nanmax(np.where(np.isinf(best), np.nan, best)),
                        best)
        share, share_low, share_high = bootstrap_band(reached, rng)
        mean, mean_low, mean_high = bootstrap_band(best, rng)
        frames.append(pd.DataFrame({
            "target": target, "agent": agent, "budget": budget, "evaluations": at,
            "reached_share": share, "reached_low": share_low, "reached_high": share_high,
            "mean_best": mean, "best_low": mean_low, "best_high": mean_high}))
    if not frames:
        return pd.DataFrame(columns=CURVE_COLUMNS)
    return pd.concat(frames, ignore_index=True)


FOUND_COLUMNS = ("target", "agent", "budget", "run", "score", "x", "y", "z", "target_score",
                 "argmin_x", "argmin_y", "argmin_z")


def found_locations(full: pd.DataFrame, targets: pd.DataFrame) -> pd.DataFrame:
    """Per (target, agent, budget) of the runs that went to their budget, the best location
    they kept (the lowest score; among ties the most symmetric), beside the target's own most
    symmetric cell (the landscape's argmin)."""
    rows = []
    for (target, agent, budget), cell in (full.groupby(CELL, sort=False) if len(full) else ()):
        cell = cell[cell["best_score"] == cell["best_score"].min()].dropna(subset=["found_x"])
        if cell.empty:
            continue
        points = cell[["found_x", "found_y", "found_z"]].to_numpy()
        best = cell.iloc[most_symmetric(points)]
        truth = targets.set_index("target").loc[target]
        rows.append({"target": target, "agent": agent, "budget": budget, "run": best["run"],
                     "score": best["best_score"], "x": best["found_x"], "y": best["found_y"],
                     "z": best["found_z"], "target_score": truth["score"],
                     "argmin_x": truth["x"], "argmin_y": truth["y"], "argmin_z": truth["z"]})
    return pd.DataFrame(rows, columns=FOUND_COLUMNS)
