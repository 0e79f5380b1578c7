"""What the learning study's runs say: per cell (target, agent, budget) the success rate with
its Wilson interval and the evaluations to the target; each learner against the random walk and
random sampling; best-so-far and success curves with bootstrap bands; the location each agent
found."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..landscape.stats import most_symmetric
from ..learning.statistics import best_so_far, bootstrap_band, censored_median, compare, wilson

CELL = ["target", "agent", "budget"]
REFERENCES = ("randomwalk", "random")
"""What every learner is compared with: the same moves without learning, and plain sampling."""
CURVE_POINTS = 40


def summary(runs: pd.DataFrame) -> pd.DataFrame:
    """One row per (target, agent, budget), in the runs' order."""
    rows = []
    for (target, agent, budget), cell in runs.groupby(CELL, sort=False):
        successes, n = int(cell["reached"].sum()), len(cell)
        low, high = wilson(successes, n)
        evaluations = cell["evaluations_to_target"].to_numpy(dtype=float)
        row = {"target": target, "agent": agent, "budget": budget,
               "steps": cell["steps"].iloc[0], "time_cap_s": cell["time_cap_s"].iloc[0],
               "n_runs": n, "successes": successes, "success_rate": successes / n,
               "ci_low": low, "ci_high": high,
               "median_evals_to_target": censored_median(evaluations),
               "censored": n - successes,
               "median_best_score": cell["best_score"].median(),
               "worst_best_score": cell["best_score"].max(),
               "target_score": cell["target_score"].iloc[0],
               "median_evaluations": cell["evaluations"].median(),
               "median_steps_per_s": cell["steps_per_s"].median()}
        walks = cell[cell["rollouts"] > 0] if "rollout_reached" in cell else cell.iloc[:0]
        if len(walks):
            reached, total = int(walks["rollout_reached"].sum()), int(walks["rollouts"].sum())
            low, high = wilson(reached, total)
            row.update(rollouts=total, rollout_limit=int(walks["rollout_limit"].iloc[0]),
                       rollout_reached=reached, rollout_rate=reached / total,
                       rollout_ci_low=low, rollout_ci_high=high,
                       rollout_mean_steps=walks["rollout_mean_steps"].mean())
        rows.append(row)
    return pd.DataFrame(rows)


COMPARISON_COLUMNS = ("target", "budget", "agent", "versus", "n_agent", "n_versus",
                      "successes_agent", "successes_versus", "median_agent", "median_versus",
                      "p_mannwhitney", "cliffs_delta", "p_fisher", "verdict")


def comparisons(runs: pd.DataFrame, learners: tuple[str, ...]) -> pd.DataFrame:
    """Each learner against each reference agent, per target and budget, on evaluations to
    the target (censored runs last): p-values and Cliff's delta (> 0: the learner sooner).
    Where no reference agent ran (the paper's own protocol: Q-learning and DQN), the first
    learner is compared with each other learner instead."""
    references = [r for r in REFERENCES if r in set(runs["agent"])]
    if not references:
        learners, references = learners[:1], list(learners[1:])
    rows = []
    for (target, budget), group in runs.groupby(["target", "budget"], sort=False):
        by_agent = {a: g["evaluations_to_target"].to_numpy(dtype=float)
                    for a, g in group.groupby("agent")}
        for learner in learners:
            for reference in references:
                if learner not in by_agent or reference not in by_agent:
                    continue
                a, b = by_agent[learner], by_agent[reference]
                test = compare(a, b)
                rows.append({"target": target, "budget": budget, "agent": learner,
                             "versus": reference, "n_agent": len(a), "n_versus": len(b),
                             "successes_agent": int((~np.isnan(a)).sum()),
                             "successes_versus": int((~np.isnan(b)).sum()),
                             "median_agent": censored_median(a),
                             "median_versus": censored_median(b), **test,
                             "verdict": verdict(test)})
    return pd.DataFrame(rows, columns=list(COMPARISON_COLUMNS))


def verdict(test: dict, alpha: float = 0.05) -> str:
    """``better``, ``worse`` or ``no difference`` at level ``alpha`` (two-sided rank test)."""
    if test["p_mannwhitney"] >= alpha:
        return "no difference"
    return "better" if test["cliffs_delta"] > 0 else "worse"


CURVE_COLUMNS = ("target", "agent", "budget", "evaluations", "reached_share", "reached_low",
                 "reached_high", "mean_best", "best_low", "best_high")


def curves(runs: pd.DataFrame, traces: pd.DataFrame, seed: int) -> pd.DataFrame:
    """Per step-budgeted cell, at log-spaced evaluation counts: the share of runs that have
    reached the target and the mean best score so far, each with a 95 % bootstrap band (no rows
    when every budget is a wall-clock cap, as in the paper's own protocol: runs that stop at a
    time do not share an evaluation axis)."""
    rng = np.random.default_rng(seed)
    frames = []
    runs = runs[runs["steps"].notna()]
    by_run = {key: t for key, t in traces.groupby([*CELL, "run"], sort=False)}
    for (target, agent, budget), cell in runs.groupby(CELL, sort=False):
        steps = int(cell["steps"].iloc[0])
        at = np.unique(np.geomspace(1, steps, CURVE_POINTS).round().astype(int))
        reached = (cell["evaluations_to_target"].to_numpy(dtype=float)[:, None]
                   <= at[None, :]).astype(float)
        best = []
        for run in cell["run"]:
            trace = by_run[(target, agent, budget, run)]
            best.append(best_so_far(trace["step"].to_numpy(), trace["best_score"].to_numpy(),
                                    at))
        best = np.array(best)
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


def found_locations(runs: pd.DataFrame, targets: pd.DataFrame) -> pd.DataFrame:
    """Per cell, the best location its runs found (the lowest score; among ties the most
    symmetric), beside the target's own most symmetric cell (the landscape's argmin)."""
    rows = []
    for (target, agent, budget), cell in runs.groupby(CELL, sort=False):
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
    return pd.DataFrame(rows)
