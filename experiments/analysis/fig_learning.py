"""Figures of the learning study, one panel per target: (1) the minimum score of every run, per
agent and paper-rate budget, as counts of runs at the optimum and at each whole step above it
(the paper drew a box plot; on 2-4 score values its boxes are lines); (2) the evaluations each
run needed to reach the target, censored runs drawn at their budget; (3) the share of runs that
have reached the target and (4) the mean best score so far, against evaluations, with 95 %
bootstrap bands and every budget of the three mappings marked; (5) greedy rollouts of the
learned policies against the random walk. Reads results/learning/ only."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import seaborn as sns
from common import (
    SEED,
    box_and_dots,
    caption,
    integer_axis,
    is_integral,
    n_text,
    plot_kind,
    read,
    save,
    share_of_grid,
)
from learning_tables import AGENT_NAMES, PAPER_RATE
from matplotlib.patches import Patch

COLOURS = dict(zip(AGENT_NAMES, sns.color_palette("tab10", n_colors=len(AGENT_NAMES)),
                   strict=True))
# Steps above the optimum: green at it, then warmer; the last level collects the rest.
LEVELS = ["at the optimum", "above it by a tie-break", "1 above", "2 above", "3 above",
          "4 or more above"]
LEVEL_COLOURS = ["#1a9850", "#a6d96a", "#fee08b", "#fc8d59", "#d73027", "#7f0000"]
HATCHES = ["", "////", "..", "xx"]  # one per budget, so that colour is left to the score
SHARE_NOTE = ("Share of the grid: of all its points, infeasible ones included.")


def panels(n: int, width: float = 4.2, height: float = 3.2):
    cols = min(3, n)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows), squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    return fig, list(axes.flat[:n])


def agents_in(frame: pd.DataFrame) -> list[str]:
    return [a for a in AGENT_NAMES if a in set(frame["agent"])]


def agent_ticks(ax, order: list[str]) -> None:
    ax.set_xticks(range(len(order)), [AGENT_NAMES[a].replace(" (", "\n(") for a in order],
                  fontsize=7, rotation=30, ha="right")
    ax.set_xlim(-0.5, len(order) - 0.5)
    ax.set_xlabel("")


def drawn_budgets(runs: pd.DataFrame) -> list[str]:
    """The budgets the per-run panels show: the step budgets at the paper's rate, smallest
    first (the other mappings are points of the curves); with none (the paper's own
    protocol), the wall-clock caps."""
    stepped = runs[runs["mapping"] == PAPER_RATE]
    if stepped.empty:
        return list(dict.fromkeys(runs.sort_values("time_cap_s")["budget"]))
    return list(dict.fromkeys(stepped.sort_values("steps")["budget"]))


def offsets(n_budgets: int) -> tuple[np.ndarray, float]:
    """Each budget's offset from its agent's x, and the width of one budget's bar or box."""
    width = 0.8 / n_budgets
    return -0.4 + width * (np.arange(n_budgets) + 0.5), width


def levels(best: pd.Series, optimum: float) -> pd.Series:
    """Each run's minimum as an index into LEVELS: at the optimum; above it by less than half a
    step (only the lexicographic objective, the paper's score plus a tie-break below 1, has
    such values); or whole steps above it, rounded."""
    excess = best - optimum
    steps = excess.round().astype(int)
    level = np.where(np.isclose(excess, 0, rtol=0, atol=1e-9), 0,
                     np.where(steps == 0, 1, steps + 1))
    return pd.Series(np.minimum(level, len(LEVELS) - 1), index=best.index)


def stacked_counts(ax, data: pd.DataFrame, order: list[str], budgets: list[str]) -> int:
    """Per agent and budget, a bar of runs stacked by steps above the optimum; returns the
    tallest bar (its run count)."""
    counts = pd.crosstab([data["agent"], data["budget"]], data["level"]).reindex(
        index=pd.MultiIndex.from_product([order, budgets]),
        columns=range(len(LEVELS)), fill_value=0).fillna(0)
    shift, width = offsets(len(budgets))
    for b, budget in enumerate(budgets):
        cell = counts.xs(budget, level=1).reindex(order)
        bottom = np.zeros(len(order))
        for k, colour in enumerate(LEVEL_COLOURS):
            ax.bar(np.arange(len(order)) + shift[b], cell[k], width * 0.92, bottom=bottom,
                   color=colour, hatch=HATCHES[b % len(HATCHES)], edgecolor="0.3",
                   linewidth=0.4)
            bottom += cell[k].to_numpy()
    return int(counts.sum(axis=1).max())


def min_score(runs: pd.DataFrame, targets: pd.DataFrame) -> None:
    budgets = drawn_budgets(runs)
    data = runs[runs["budget"].isin(budgets)]
    sizes = data.groupby(["target", "agent", "budget"]).size()
    fig, axes = panels(len(targets), height=3.4)
    for ax, t in zip(axes, targets.itertuples(), strict=True):
        cell = data[data["target"] == t.target]
        cell = cell.assign(level=levels(cell["best_score"], t.score))
        order = agents_in(cell)
        if plot_kind(cell["level"]) == "counts":
            top = stacked_counts(ax, cell, order, budgets)
            integer_axis(ax, "y")
            ax.set_ylim(0, top * 1.03)
            ax.set_ylabel("runs (stacked by their minimum)", fontsize=8)
            ax.grid(axis="y", color="0.85", lw=0.5, zorder=0)
            ax.set_axisbelow(True)
        else:  # many score values: the minima themselves, boxes where they inform
            shift, width = offsets(len(budgets))
            palette = sns.color_palette("tab10", n_colors=len(budgets))
            for (a, b), group in cell.groupby(["agent", "budget"], sort=False):
                i, j = order.index(a), budgets.index(b)
                box_and_dots(ax, i + shift[j], group["best_score"], palette[j], width,
                             seed=SEED + i * len(budgets) + j)
            ax.axhline(t.score, color="#d62728", ls="--", lw=1)
            if is_integral(cell["best_score"]):
                integer_axis(ax, "y", cell["best_score"])
            ax.set_ylabel(f"minimum {t.objective} of the run", fontsize=8)
        ax.set_title(f"{t.target}: optimum {t.score:g} on {share_of_grid(t.fraction)}",
                     fontsize=9)
        agent_ticks(ax, order)
    handles = [Patch(facecolor=c, edgecolor="0.3", label=f"minimum {name}")
               for c, name in zip(LEVEL_COLOURS, LEVELS, strict=True)]
    handles += [Patch(facecolor="white", edgecolor="0.3", hatch=HATCHES[b % len(HATCHES)],
                      label=budget) for b, budget in enumerate(budgets)]
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=7,
               bbox_to_anchor=(0.5, 0.965), frameon=False)
    fig.suptitle("Minimum score per run: runs at the optimum and steps above it "
                 f"({n_text(sizes, 'runs per bar')})", y=0.995)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    caption(fig, "Each bar counts one agent's runs at one budget by the minimum score the "
                 "run found. The lexicographic objective is the paper's score plus a tie-break "
                 "below 1: its steps are the paper score's (rounded), and a run at the paper "
                 "score's minimum but not the tie-break's is 'above it by a tie-break'. "
                 + SHARE_NOTE)
    save(fig, "learning_min_score.png")


def evaluations_to_target(runs: pd.DataFrame, targets: pd.DataFrame) -> None:
    budgets = drawn_budgets(runs)
    data = runs[runs["budget"].isin(budgets)].assign(
        hit=lambda f: f["reached"].astype(str) == "True",
        evals=lambda f: f["evaluations_to_target"].clip(lower=1))
    sizes = data.groupby(["target", "agent", "budget"]).size()
    palette = sns.color_palette("tab10", n_colors=len(budgets))
    shift, width = offsets(len(budgets))
    fig, axes = panels(len(targets), height=3.4)
    for ax, t in zip(axes, targets.itertuples(), strict=True):
        cell = data[data["target"] == t.target]
        order = agents_in(cell)
        for (a, b), group in cell.groupby(["agent", "budget"], sort=False):
            i, j = order.index(a), budgets.index(b)
            x, seed = i + shift[j], SEED + i * len(budgets) + j
            box_and_dots(ax, x, group.loc[group["hit"], "evals"], palette[j], width, seed)
            missed = group.loc[~group["hit"], "evaluations"].to_numpy(dtype=float)
            # Censored: never reached within the budget (or the cap), drawn at the budget.
            # Spread within the box's width, however many (up to 100 runs a box).
            spread = np.linspace(-0.4, 0.4, missed.size) * width if missed.size > 1 else \
                np.zeros(missed.size)
            ax.scatter(x + spread, missed,
                       marker="x", color="#d62728", s=14, lw=0.8, zorder=3)
            ax.text(x, 0.97, f"{int(group['hit'].sum())}/{len(group)}", fontsize=5,
                    ha="center", va="top", transform=ax.get_xaxis_transform())
        ax.set_yscale("log")
        low, high = cell["evals"].min(), cell["evaluations"].max()
        ax.set_ylim(0.5 if not low > 1 else low / 2, high * 12)  # headroom for the k/n row
        ax.set_title(f"{t.target}: target on {share_of_grid(t.fraction)}", fontsize=9)
        ax.set_ylabel("evaluations to the target", fontsize=8)
        agent_ticks(ax, order)
    handles = [Patch(facecolor=c, label=b) for c, b in zip(palette, budgets, strict=True)]
    handles.append(plt.Line2D([], [], marker="x", color="#d62728", ls="",
                              label="never reached (drawn at the budget)"))
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=7,
               bbox_to_anchor=(0.5, 0.965), frameon=False)
    fig.suptitle(f"Evaluations to the target, one dot per run ({n_text(sizes, 'runs')} per "
                 "agent and budget; k/n: runs that reached it)", y=0.995)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    caption(fig, "A box is drawn where at least 5 runs reached the target, at 5 or more "
                 f"distinct evaluation counts; otherwise the dots alone. {SHARE_NOTE}")
    save(fig, "learning_evaluations.png")


def curves(curve: pd.DataFrame, runs: pd.DataFrame, targets: pd.DataFrame, value: str,
           low: str, high: str, ylabel: str, name: str, title: str) -> None:
    """One curve per agent, each up to the budget its runs went to (DQN's is the paper-rate
    one), with every step budget marked: a budget's success rate is the curve's value there."""
    if curve.empty:  # wall-clock caps only: no shared evaluation axis, no curves
        return
    stepped = runs.dropna(subset=["mapping"])
    marks = stepped.drop_duplicates("budget").sort_values("steps")
    sizes = stepped.drop_duplicates(["target", "agent", "run"]).groupby(
        ["target", "agent"]).size()
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
            if is_integral([t.score]):  # a mean of integer scores, on the scores' ticks
                integer_axis(ax, "y")
        else:
            ax.set_ylim(-0.03, 1.03)
        for mark in marks.itertuples():
            ax.axvline(mark.steps, color="0.6", lw=0.6,
                       ls="-" if mark.mapping == PAPER_RATE else ":", zorder=0)
        ax.set_xscale("log")
        ax.set_title(t.target, fontsize=9)
        ax.set_xlabel("evaluations (log)", fontsize=8)
        ax.set_ylabel(ylabel, fontsize=8)
    axes[0].legend(fontsize=6)
    fig.suptitle(f"{title} (mean of {n_text(sizes, 'runs per curve')}, 95 % bootstrap band)")
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    caption(fig, "Vertical lines: the budgets, the paper's 2- and 5-minute caps at 315 "
                 "evaluations/s (solid) and at a tenth and ten times that rate (dotted). "
                 "A run stops at its first target cell and keeps it: its success and best score "
                 "carry to every larger budget.")
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
        zero = rate == 0  # a bar of height 0 is invisible: say it, above its interval
        for xz, top in zip(x[zero], rows["rollout_ci_high"].to_numpy()[zero], strict=True):
            ax.text(xz, np.nan_to_num(top) + 0.01, "0", ha="center", va="bottom", fontsize=6,
                    color=COLOURS[agent])
    ax.set_xticks(range(len(target_names)), target_names, fontsize=8, rotation=20)
    ax.set_ylabel("share of walks that reach the target")
    ax.set_ylim(0, 1.05)
    ax.set_title("Greedy rollouts of the final policy from the same random starts "
                 f"({n_text(walks['rollouts'], 'walks per bar')}; 95 % Wilson interval)",
                 fontsize=10)
    ax.legend(fontsize=7)
    save(fig, "learning_rollouts.png")


def main() -> None:
    runs, targets = read("learning/runs.csv"), read("learning/targets.csv")
    summary, curve = read("learning/summary.csv"), read("learning/curves.csv")
    min_score(runs, targets)
    evaluations_to_target(runs, targets)
    curves(curve, runs, targets, "reached_share", "reached_low", "reached_high",
           "share of runs at the target", "learning_success.png",
           "Runs that reached the target")
    curves(curve, runs, targets, "mean_best", "best_low", "best_high", "mean best score so far",
           "learning_best_so_far.png", "Best score so far")
    rollouts(summary)


if __name__ == "__main__":
    main()
