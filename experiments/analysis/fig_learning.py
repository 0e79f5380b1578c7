"""Figures of the learning study, one panel per target: (1) the minimum score of every run, per
agent and paper-rate budget, as counts of runs at the optimum and at each whole step above it
(the paper drew a box plot; on 2-4 score values its boxes are lines); (2) the evaluations each
run needed to reach the target, censored runs drawn at their budget; (3) the share of runs that
have reached the target and (4) the mean best score so far, against evaluations, with 95 %
bootstrap bands and every budget of the three mappings marked; (5) greedy rollouts of the
learned policies against the random walk. Reads results/learning/ only.

Targets and budgets are named in words (:func:`target_words`, :func:`budget_words`), not by
the study's keys: a reader has the figure, not targets.csv."""

from __future__ import annotations

import math
import textwrap

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import seaborn as sns
from common import (
    REBA_AB_NOTE,
    SCORE_WORDS,
    SEED,
    box_and_dots,
    caption,
    integer_axis,
    is_integral,
    n_text,
    percent,
    plot_kind,
    read,
    save,
    share_of_grid,
    worker_words,
)
from learning_tables import AGENT_NAMES, PAPER_RATE
from matplotlib.patches import Patch

COLOURS = dict(zip(AGENT_NAMES, sns.color_palette("tab10", len(AGENT_NAMES)), strict=True))
# Q-learning, its adaptive variant and the random walk draw nearly the same curves (the study's
# finding): each gets its own dashes and markers, and the curves are drawn in this order, so
# that Q-learning, the paper's learner, lies on top and the others show beside it.
DRAW_ORDER = ["random-draws", "hillclimb", "randomwalk", "qlearning-adaptive", "dqn", "qlearning"]
STYLES = {agent: {"ls": ls, "lw": lw, "marker": marker} for agent, ls, lw, marker in (
    ("qlearning", "-", 1.8, "o"), ("qlearning-adaptive", (0, (5, 2)), 1.3, "s"),
    ("randomwalk", (0, (1, 1.5)), 1.6, "^"), ("dqn", "-", 1.2, "D"),
    ("random-draws", "-", 1.2, "v"), ("hillclimb", (0, (5, 1.5, 1, 1.5)), 1.2, "P"))}
BOUNDARY_WORDS = {"body": "over the region derived from the body", "paper-code": "over the "
                  "published code's region"}
# Steps above the optimum, green at it, then warmer (the last collects the rest).
LEVELS = ["at the optimum", "above it by a tie-break", *(f"{k} above" for k in (1, 2, 3)),
          "4 or more above"]
LEVEL_COLOURS = ["#1a9850", "#a6d96a", "#fee08b", "#fc8d59", "#d73027", "#7f0000"]
HATCHES = ["", "////", "..", "xx"]  # one per budget, so that colour is left to the score
SHARE_NOTE = "Share of the grid: of all its points, infeasible ones included."
DEFAULT_NOTE = ("Every target is the 50th-percentile man's, keeping the box in view, over the "
                "published code's region, unless its title says otherwise.")
TIE_BREAK_NOTE = ("'With the best tie-breaks': the cells of paper score 4 with the lowest "
                  "REBA Table A + Table B, then RULA, then nearest the midline.")


def defaults(targets: pd.DataFrame) -> dict[str, str]:
    """The worker, gaze and boundary most targets share: a title names only departures."""
    return {"worker": targets["worker"].mode()[0], "gaze": targets["gaze"].mode()[0],
            "boundary": targets["grid"].map(boundary).mode()[0]}


def boundary(grid: str) -> str:
    """``paper-code`` from ``"grid ... in boundary 'paper-code'"``."""
    return grid.rsplit("boundary ", 1)[-1].strip("'")


def target_words(t, default: dict[str, str]) -> tuple[str, str]:
    """A target as a reader says it: what is sought (``"paper score 4"``) and, where they
    differ from ``default``, for whom and where (``""`` where nothing differs)."""
    score = SCORE_WORDS.get(t.objective, t.objective)
    if t.objective == "lexicographic":  # the paper's score, then three tie-breaks
        sought = f"paper score {math.floor(t.score):g} with the best tie-breaks"
    elif t.goal == "reward":  # the paper's reward: the score plus a symmetry term
        sought = f"{score} {t.score:g} nearest the midline"
    else:
        sought = f"{score} {t.score:g}"
    conditions = []
    if t.worker != default["worker"]:
        conditions.append(f"the {worker_words(t.worker)}")
    if t.gaze != default["gaze"]:
        conditions.append("box need not stay in view" if t.gaze == "off" else "gaze on")
    where = boundary(t.grid)
    if where != default["boundary"]:
        conditions.append(BOUNDARY_WORDS.get(where, f"region {where}"))
    return sought, ", ".join(conditions)


def target_title(t, default: dict[str, str]) -> str:
    """A panel's title: the target, then its conditions and its share of the grid."""
    sought, conditions = target_words(t, default)
    share = f"on {share_of_grid(t.fraction)}"
    return f"target: {sought}\n" + (f"{conditions}; {share}" if conditions else share)


def target_label(t, default: dict[str, str]) -> str:
    """A target in two short lines, for a tick label."""
    sought, conditions = target_words(t, default)
    sought = sought.replace(" with the best tie-breaks", ", best tie-breaks")
    return "\n".join(textwrap.fill(w, 18) for w in (sought, conditions) if w)


def budget_words(runs: pd.DataFrame) -> dict[str, str]:
    """Each budget in words: ``"the paper's 2-min cap (37,800 evaluations)"``; at another
    rate, the rate's multiple of the paper's."""
    words = {}
    for b in runs.drop_duplicates("budget").itertuples():
        if b.mapping != b.mapping:  # a wall-clock cap: no step count
            words[b.budget] = f"{b.time_cap_s:g} s of wall clock"
            continue
        rate = "" if b.mapping == PAPER_RATE else f" at {b.mapping / PAPER_RATE:g}x its rate"
        words[b.budget] = (f"the paper's {b.cap_min:g}-min cap{rate} "
                           f"({int(b.steps):,} evaluations)")
    return words


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
    ordered = runs.sort_values("time_cap_s") if stepped.empty else stepped.sort_values("steps")
    return list(dict.fromkeys(ordered["budget"]))


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


def same_panels(data: pd.DataFrame, targets: pd.DataFrame) -> list[list]:
    """The targets in groups whose panels would draw the same counts (REBA 1 and REBA Table
    A + Table B 2 are the same cells, and every run reaches them): one panel per group."""
    groups: dict[tuple, list] = {}
    for t in targets.itertuples():
        cell = data[data["target"] == t.target]
        key = tuple(sorted(zip(cell["agent"], cell["budget"], cell["run"],
                               levels(cell["best_score"], t.score), strict=True)))
        groups.setdefault(key, []).append(t)
    return list(groups.values())


def merged_title(group: list, default: dict[str, str]) -> str:
    """One title for targets whose panels are the same."""
    if len(group) == 1:
        return target_title(group[0], default)
    named = [", ".join(w for w in target_words(t, default) if w) for t in group]
    lines, line = [], "targets: "
    for k, name in enumerate(named):  # wrapped between targets, never inside one
        piece = name + ("; " if k < len(named) - 1 else "")
        if len(line) + len(piece) > 60 and line != "targets: ":
            lines.append(line.rstrip())
            line = ""
        line += piece
    lines.append(line)
    shares = " / ".join(percent(t.fraction, 3) for t in group)
    return "\n".join(lines) + f"\nthe same counts for each; on {shares} of the grid"


def min_score(runs: pd.DataFrame, targets: pd.DataFrame) -> None:
    budgets = drawn_budgets(runs)
    words = budget_words(runs)
    default = defaults(targets)
    data = runs[runs["budget"].isin(budgets)]
    sizes = data.groupby(["target", "agent", "budget"]).size()
    groups = same_panels(data, targets)
    fig, axes = panels(len(groups), height=3.5)
    for ax, group in zip(axes, groups, strict=True):
        t = group[0]
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
            ax.set_ylabel(f"minimum {SCORE_WORDS.get(t.objective, t.objective)} of the run",
                          fontsize=8)
        ax.set_title(merged_title(group, default), fontsize=8.5)
        agent_ticks(ax, order)
    handles = [Patch(facecolor=c, edgecolor="0.3", label=f"minimum {name}")
               for c, name in zip(LEVEL_COLOURS, LEVELS, strict=True)]
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=7,
               bbox_to_anchor=(0.5, 0.975), frameon=False)
    fig.legend(handles=[Patch(facecolor="white", edgecolor="0.3",
                              hatch=HATCHES[b % len(HATCHES)], label=words[budget])
                        for b, budget in enumerate(budgets)],
               loc="upper center", ncol=len(budgets), fontsize=7,
               bbox_to_anchor=(0.5, 0.955), frameon=False)
    fig.suptitle("Minimum score per run: runs at the optimum and steps above it "
                 f"({n_text(sizes, 'runs per bar')})", y=0.995)
    fig.tight_layout(rect=(0, 0, 1, 0.935))
    caption(fig, "Each bar counts one agent's runs at one budget (left: plain, right: "
                 "hatched) by the minimum score the run found. 'Above it by a tie-break': a "
                 "run at paper score 4 without the best tie-breaks. " + TIE_BREAK_NOTE + " "
                 + REBA_AB_NOTE + ". " + DEFAULT_NOTE + " " + SHARE_NOTE)
    save(fig, "learning_min_score.png")


def evaluations_to_target(runs: pd.DataFrame, targets: pd.DataFrame) -> None:
    budgets = drawn_budgets(runs)
    data = runs[runs["budget"].isin(budgets)].assign(
        hit=lambda f: f["reached"].astype(str) == "True",
        evals=lambda f: f["evaluations_to_target"].clip(lower=1))
    sizes = data.groupby(["target", "agent", "budget"]).size()
    words, default = budget_words(runs), defaults(targets)
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
            # Neighbouring budgets' counts on two rows: side by side they run together.
            ax.text(x, 0.975 - 0.065 * (j % 2), f"{int(group['hit'].sum())}/{len(group)}",
                    fontsize=5, ha="center", va="top", color=palette[j],
                    transform=ax.get_xaxis_transform())
        ax.set_yscale("log")
        low, high = cell["evals"].min(), cell["evaluations"].max()
        ax.set_ylim(0.5 if not low > 1 else low / 2, high * 60)  # headroom for the k/n rows
        ax.set_title(target_title(t, default), fontsize=8.5)
        ax.set_ylabel("evaluations to the target", fontsize=8)
        agent_ticks(ax, order)
    handles = [Patch(facecolor=c, label=words[b]) for c, b in zip(palette, budgets,
                                                                  strict=True)]
    handles.append(plt.Line2D([], [], marker="x", color="#d62728", ls="",
                              label="never reached (drawn at the budget)"))
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=7,
               bbox_to_anchor=(0.5, 0.965), frameon=False)
    fig.suptitle(f"Evaluations to the target, one dot per run ({n_text(sizes, 'runs')} per "
                 "agent and budget; k/n: runs that reached it)", y=0.995)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    caption(fig, "A box is drawn where at least 5 runs reached the target, at 5 or more "
                 "distinct evaluation counts; otherwise the dots alone. k/n above each box, in "
                 f"its budget's colour. {TIE_BREAK_NOTE} {REBA_AB_NOTE}. {DEFAULT_NOTE} "
                 f"{SHARE_NOTE}")
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
    default = defaults(targets)
    order = [a for a in DRAW_ORDER if a in set(curve["agent"])]
    order += [a for a in agents_in(curve) if a not in order]
    longest = curve["evaluations"].max()
    stops = []  # the agents whose curves end at a smaller budget than the others'
    fig, axes = panels(len(targets), height=3.4)
    for ax, t in zip(axes, targets.itertuples(), strict=True):
        for k, agent in enumerate(order):
            c = curve[(curve["target"] == t.target) & (curve["agent"] == agent)]
            if c.empty:
                continue
            style = STYLES.get(agent, {"ls": "-", "lw": 1.2, "marker": "o"})
            # Markers every 6 points, each agent's shifted, so that they do not coincide.
            ax.plot(c["evaluations"], c[value], color=COLOURS[agent], ls=style["ls"],
                    lw=style["lw"], marker=style["marker"], ms=3.5, markevery=(k % 6, 6),
                    label=AGENT_NAMES[agent], zorder=3 + k)
            ax.fill_between(c["evaluations"], c[low], c[high], color=COLOURS[agent],
                            alpha=0.12, lw=0, zorder=1)
            end = c["evaluations"].max()
            if end < longest:  # say where and why the curve stops
                stops.append((agent, int(end)))
                y_end = c.loc[c["evaluations"].idxmax(), value]
                ax.plot([end], [y_end], "|", color=COLOURS[agent], ms=12, mew=2,
                        zorder=3 + len(order))
                # Right of the end, where the other curves have levelled off: below them
                # for the share reached (at 1), above them for the best score (at the optimum).
                ax.annotate(f"{AGENT_NAMES[agent]} ends:\nits budget, {int(end):,}",
                            (end, y_end), xytext=(8, -45 if value == "reached_share" else 35),
                            textcoords="offset points", ha="left", va="center", fontsize=6.5,
                            color=COLOURS[agent],
                            arrowprops={"arrowstyle": "-", "color": COLOURS[agent], "lw": 0.6})
        if value == "mean_best":  # black: red is DQN's
            ax.axhline(t.score, color="black", ls="--", lw=0.8, zorder=2,
                       label="the target's score")
            if is_integral([t.score]):  # a mean of integer scores, on the scores' ticks
                integer_axis(ax, "y")
        else:
            ax.set_ylim(-0.03, 1.03)
        for mark in marks.itertuples():
            ax.axvline(mark.steps, color="0.6", lw=0.6,
                       ls="-" if mark.mapping == PAPER_RATE else ":", zorder=0)
        ax.set_xscale("log")
        ax.set_title(target_title(t, default), fontsize=8.5)
        ax.set_xlabel("evaluations (log)", fontsize=8)
        ax.set_ylabel(ylabel, fontsize=8)
    handles, labels = axes[0].get_legend_handles_labels()
    shown = dict(zip(labels, handles, strict=True))
    listed = [AGENT_NAMES[a] for a in agents_in(curve) if AGENT_NAMES[a] in shown]
    listed += [n for n in shown if n not in listed]
    fig.legend([shown[n] for n in listed], listed, loc="upper center", ncol=len(listed),
               fontsize=7.5, bbox_to_anchor=(0.5, 0.965), frameon=False)
    fig.suptitle(f"{title} (mean of {n_text(sizes, 'runs per curve')}, 95 % bootstrap band)",
                 y=0.995)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    ends = "; ".join(f"{AGENT_NAMES[a]}'s at {end:,}, the largest budget it was run to"
                     for a, end in dict(stops).items())
    caption(fig, "Vertical lines: the budgets, the paper's 2- and 5-minute caps at 315 "
                 "evaluations/s (solid) and at a tenth and ten times that rate (dotted). "
                 "A run stops at its first target cell and keeps it: its success and best score "
                 f"carry to every larger budget. Every curve runs to {int(longest):,} "
                 "evaluations, the largest budget" + (f", but {ends}" if ends else "") + ". "
                 "Q-learning (solid) is drawn over the others; where another agent's curve "
                 f"meets it, that agent's dashes and markers show beside it. {TIE_BREAK_NOTE} "
                 f"{REBA_AB_NOTE}. {DEFAULT_NOTE}")
    save(fig, name)


def rollouts(summary: pd.DataFrame, targets: pd.DataFrame) -> None:
    if "rollouts" not in summary:  # no run was rolled out (the paper's own protocol)
        return
    walks = summary.dropna(subset=["rollouts"])
    if walks.empty:
        return
    agents = [a for a in ("qlearning", "qlearning-adaptive", "dqn", "randomwalk")
              if a in set(walks["agent"])]
    target_names = list(dict.fromkeys(walks["target"]))
    default = defaults(targets)
    words = {t.target: target_label(t, default) for t in targets.itertuples()}
    fig, ax = plt.subplots(figsize=(max(7, 1.25 * len(target_names)), 3.9))
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
    ax.set_xticks(range(len(target_names)), [words.get(n, n) for n in target_names],
                  fontsize=7)
    ax.set_ylabel("share of walks that reach the target")
    ax.set_ylim(0, 1.05)
    ax.set_title("Greedy rollouts of the final policy from the same random starts "
                 f"({n_text(walks['rollouts'], 'walks per bar')}; 95 % Wilson interval)",
                 fontsize=10)
    ax.legend(fontsize=7)
    fig.tight_layout()
    caption(fig, "A walk reaches the target when the greedy policy, from a random start, steps "
                 "onto a target cell. " + TIE_BREAK_NOTE + " " + REBA_AB_NOTE + ". "
                 + DEFAULT_NOTE.replace("its title", "its label"), width=140)
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
    rollouts(summary, targets)


if __name__ == "__main__":
    main()
