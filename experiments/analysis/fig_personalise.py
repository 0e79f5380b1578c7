"""Figures of the personalisation study.

personalise.png: how many handovers each searcher needs to find one worker's own optimum with
exact answers — the share of runs that evaluated a cell at the worker's optimum (left) and
within one point of it (right) within n evaluations, per searcher, on log-scaled evaluations;
the study's budgets marked. Reads results/personalise/curves.csv and summary.csv.

personalise_measured.png: with answers as a site gets them — the share of runs whose
recommendation is a true optimum after each budget, per searcher (its own recommendation
rule: the lowest answer, or the preferred location), with 95 % intervals over workers
(each searcher's points set a little apart); a
panel per answer model, in model (top) and out of model (bottom). Reads
results/personalise/measured_summary.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
from common import read, save

from ergohandover.search.registry import SEARCHERS

TITLES = {"optimum": "the worker's own optimum", "within_1": "within one point of it"}


def warm_started(name: str) -> bool:
    """A variant that always starts from the worker's prior (the registry says which)."""
    return name in SEARCHERS and SEARCHERS[name].prior == "needs"


def main() -> None:
    curves = read("personalise/curves.csv")
    summary = read("personalise/summary.csv")
    first = summary.iloc[0]
    searchers = list(dict.fromkeys(curves["searcher"]))
    budgets = sorted(summary["budget"].unique())
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), sharey=True)
    colours = plt.get_cmap("tab20")
    for ax, target in zip(axes, ("optimum", "within_1"), strict=True):
        for i, name in enumerate(searchers):
            line = curves[(curves["searcher"] == name) & (curves["target"] == target)]
            ax.step(line["evaluations"], line["success_rate"], where="post", color=colours(i),
                    linestyle="--" if warm_started(name) else "-", label=name)
        for budget in budgets:
            ax.axvline(budget, color="grey", linewidth=0.5, alpha=0.5)
        ax.set_xscale("log")
        ax.set_xlabel("evaluations (real handovers)")
        ax.set_title(TITLES[target], fontsize=10)
        ax.set_ylim(0, 1.02)
    axes[0].set_ylabel("share of runs that reached it")
    axes[1].legend(fontsize=7, ncol=2, loc="lower right")
    fig.suptitle(f"Personalising the handover: N = {int(first['n_workers'])} workers x "
                 f"{int(first['n_runs']) // int(first['n_workers'])} runs per searcher",
                 fontsize=11)
    save(fig, "personalise.png")
    measured_figure()


def measured_figure() -> None:
    summary = read("personalise/measured_summary.csv")
    summary = summary[summary["rule"] != "confirm"]
    answers = list(dict.fromkeys(summary["answers"]))
    models = ["in-model", "out-of-model"]
    searchers = list(dict.fromkeys(summary["searcher"]))
    fig, axes = plt.subplots(2, len(answers), figsize=(3 * len(answers), 6.4), sharex=True,
                             sharey=True, squeeze=False)
    colours = plt.get_cmap("tab10")
    for row, model in enumerate(models):
        for col, said in enumerate(answers):
            ax = axes[row][col]
            for i, name in enumerate(searchers):
                line = summary[(summary["model"] == model) & (summary["answers"] == said)
                               & (summary["searcher"] == name)]
                # Each searcher's points a little apart, so that the intervals do not hide
                # one another (the budgets are on a log axis).
                x = line["budget"] * 1.04 ** (i - (len(searchers) - 1) / 2)
                y = line["p_regret_0"]
                ax.errorbar(x, y, yerr=[y - line["ci_low"], line["ci_high"] - y],
                            marker="o", markersize=3, linewidth=1, elinewidth=0.6, capsize=0,
                            color=colours(i), label=SEARCHERS[name].label)
            ax.set_xscale("log")
            ax.set_xticks(sorted(summary["budget"].unique()))
            ax.xaxis.set_major_formatter("{x:g}")
            ax.xaxis.set_minor_locator(plt.NullLocator())
            ax.set_title(f"{said}, {model}", fontsize=8)
            ax.set_ylim(0, 1.02)
            if row == 1:
                ax.set_xlabel("handovers")
        axes[row][0].set_ylabel("recommendation a true optimum")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=7,
               frameon=False)
    sizes = summary.groupby("model")["n_workers"].first()
    runs = int(summary["n_runs"].iloc[0]) // int(summary["n_workers"].iloc[0])
    fig.suptitle(f"Personalising with answers as a site gets them: N = {sizes['in-model']} "
                 f"workers in model, {sizes['out-of-model']} out of model, {runs} run each, "
                 "equal budgets, no stop rule", fontsize=10)
    fig.tight_layout(rect=(0, 0.05, 1, 1))  # room for the legend below the panels
    save(fig, "personalise_measured.png")


if __name__ == "__main__":
    main()
