"""Figures of the learning study, one panel per target: (1) the minimum score of every run, per
agent and budget (the paper's box plot, with the other agents beside Q-learning); (2) the
evaluations each run needed to reach the target, censored runs drawn at their budget; (3) the
share of runs that have reached the target and (4) the mean best score so far, against
evaluations, with 95 % bootstrap bands; (5) greedy rollouts of the learned policies against the
random walk. Reads results/learning/ only."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import seaborn as sns
from common import read, save
from learning_tables import AGENT_NAMES

COLOURS = dict(zip(AGENT_NAMES, sns.color_palette("tab10", n_colors=len(AGENT_NAMES)),
                   strict=True))


def panels(n: int, width: float = 4.2, height: float = 3.2):
    cols = min(3, n)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows), squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    return fig, list(axes.flat[:n])


def agents_in(frame: pd.DataFrame) -> list[str]:
    return [a for a in AGENT_NAMES if a in set(frame["agent"])]


def drawn_budgets(runs: pd.DataFrame) -> list[str]:
    """The budgets the box plots show: the step budgets, smallest first; with none (the
    paper's own protocol), the wall-clock caps."""
    stepped = runs.dropna(subset=["steps"])
    if stepped.empty:
        return list(dict.fromkeys(runs.sort_values("time_cap_s")["budget"]))
    return list(dict.fromkeys(stepped.sort_values("steps")["budget"]))


def min_score(runs: pd.DataFrame, targets: pd.DataFrame) -> None:
    budgets = drawn_budgets(runs)
    fig, axes = panels(len(targets))
    for ax, t in zip(axes, targets.itertuples(), strict=True):
        data = runs[(runs["target"] == t.target) & runs["budget"].isin(budgets)]
        order = agents_in(data)
        sns.boxplot(data=data, x="agent", y="best_score", hue="budget", order=order,
                    hue_order=budgets, ax=ax, fliersize=0, linewidth=0.8)
        # No jitter: seaborn draws it from numpy's global generator.
        sns.stripplot(data=data, x="agent", y="best_score", hue="budget", order=order,
                      hue_order=budgets, dodge=True, jitter=False, ax=ax, size=3,
                      palette="dark:#08306b", legend=False)
        ax.axhline(t.score, color="#d62728", ls="--", lw=1)
        ax.set_title(f"{t.target}: optimum {t.score:g} on {t.fraction:.3%} of the grid",
                     fontsize=9)
        ax.set_xticks(range(len(order)), [AGENT_NAMES[a].replace(" (", "\n(") for a in order],
                      fontsize=7, rotation=30, ha="right")
        ax.set_xlabel("")
        ax.set_ylabel(f"minimum {t.objective} of the run", fontsize=8)
        ax.legend(fontsize=7, title=None) if ax is axes[0] else ax.get_legend().remove()
    fig.suptitle("Minimum score per run (dashed: the exhaustive optimum)")
    fig.tight_layout()
    save(fig, "learning_min_score.png")


def evaluations_to_target(runs: pd.DataFrame, targets: pd.DataFrame) -> None:
    budgets = drawn_budgets(runs)
    fig, axes = panels(len(targets))
    for ax, t in zip(axes, targets.itertuples(), strict=True):
        data = runs[(runs["target"] == t.target) & runs["budget"].isin(budgets)].copy()
        order = agents_in(data)
        reached = data[data["reached"].astype(str) == "True"].copy()
        reached["evals"] = reached["evaluations_to_target"].clip(lower=1)
        if len(reached):
            sns.boxplot(data=reached, x="agent", y="evals", hue="budget", order=order,
                        hue_order=budgets, ax=ax, fliersize=0, linewidth=0.8, log_scale=True)
        ax.set_yscale("log")
        width = 0.8 / len(budgets)
        for b, budget in enumerate(budgets):
            for i, agent in enumerate(order):
                cell = data[(data["agent"] == agent) & (data["budget"] == budget)]
                if cell.empty:
                    continue
                x = i - 0.4 + width * (b + 0.5)
                missed = cell[cell["reached"].astype(str) != "True"]
                if len(missed):  # censored: never reached within the budget (or the cap)
                    ax.scatter([x] * len(missed), missed["evaluations"],
                               marker="x", color="#d62728", s=18, zorder=3)
                ax.text(x, 0.02, f"{len(cell) - len(missed)}/{len(cell)}", fontsize=6,
                        ha="center", transform=ax.get_xaxis_transform())
        ax.set_title(f"{t.target} ({t.fraction:.3%} of the grid)", fontsize=9)
        ax.set_xticks(range(len(order)), [AGENT_NAMES[a].replace(" (", "\n(") for a in order],
                      fontsize=7, rotation=30, ha="right")
        ax.set_xlabel("")
        ax.set_ylabel("evaluations to the target", fontsize=8)
        legend = ax.get_legend()
        if legend is not None and ax is not axes[0]:
            legend.remove()
    fig.suptitle("Evaluations to the target (x: never reached within the budget; "
                 "k/n: runs that reached it)")
    fig.tight_layout()
    save(fig, "learning_evaluations.png")


def curves(curve: pd.DataFrame, targets: pd.DataFrame, value: str, low: str, high: str,
           ylabel: str, name: str, title: str) -> None:
    if curve.empty:  # wall-clock caps only: no shared evaluation axis, no curves
        return
    budget = curve.sort_values("evaluations")["budget"].iloc[-1]  # the largest budget
    curve = curve[curve["budget"] == budget]
    fig, axes = panels(len(targets))
    for ax, t in zip(axes, targets.itertuples(), strict=True):
        for agent in agents_in(curve):
            c = curve[(curve["target"] == t.target) & (curve["agent"] == agent)]
            if c.empty:
                continue
            ax.plot(c["evaluations"], c[value], color=COLOURS[agent], lw=1.2,
                    label=AGENT_NAMES[agent])
            ax.fill_between(c["evaluations"], c[low], c[high], color=COLOURS[agent], alpha=0.2,
                            lw=0)
        if value == "mean_best":
            ax.axhline(t.score, color="#d62728", ls="--", lw=1)
        ax.set_xscale("log")
        ax.set_title(t.target, fontsize=9)
        ax.set_xlabel("evaluations (log)", fontsize=8)
        ax.set_ylabel(ylabel, fontsize=8)
    axes[0].legend(fontsize=6)
    fig.suptitle(f"{title} at {budget} (mean of runs, 95 % bootstrap band)")
    fig.tight_layout()
    save(fig, name)


def rollouts(summary: pd.DataFrame) -> None:
    if "rollouts" not in summary:  # no run was rolled out (the paper's own protocol)
        return
    walks = summary.dropna(subset=["rollouts"])
    if walks.empty:
        return
    agents = [a for a in ("qlearning", "qlearning-adaptive", "dqn", "randomwalk")
              if a in set(walks["agent"])]
    target_names = list(dict.fromkeys(walks["target"]))
    fig, ax = plt.subplots(figsize=(max(7, 0.9 * len(target_names)), 3.6))
    width = 0.8 / len(agents)
    for i, agent in enumerate(agents):
        rows = walks[walks["agent"] == agent].set_index("target").reindex(target_names)
        x = np.arange(len(target_names)) - 0.4 + width * (i + 0.5)
        rate = rows["rollout_rate"].to_numpy()
        err = np.clip(np.vstack([rate - rows["rollout_ci_low"],
                                 rows["rollout_ci_high"] - rate]), 0, None)
        ax.bar(x, rate, width, color=COLOURS[agent], label=AGENT_NAMES[agent],
               yerr=np.nan_to_num(err), capsize=2, error_kw={"lw": 0.8})
    ax.set_xticks(range(len(target_names)), target_names, fontsize=8, rotation=20)
    ax.set_ylabel("walks that reach the target")
    ax.set_ylim(0, 1.05)
    ax.set_title("Greedy rollouts of the final policy from the same random starts "
                 "(95 % Wilson interval)", fontsize=10)
    ax.legend(fontsize=7)
    save(fig, "learning_rollouts.png")


def main() -> None:
    runs, targets = read("learning/runs.csv"), read("learning/targets.csv")
    summary, curve = read("learning/summary.csv"), read("learning/curves.csv")
    min_score(runs, targets)
    evaluations_to_target(runs, targets)
    curves(curve, targets, "reached_share", "reached_low", "reached_high",
           "share of runs at the target", "learning_success.png", "Runs that reached the target")
    curves(curve, targets, "mean_best", "best_low", "best_high", "best score so far",
           "learning_best_so_far.png", "Best score so far")
    rollouts(summary)


if __name__ == "__main__":
    main()
