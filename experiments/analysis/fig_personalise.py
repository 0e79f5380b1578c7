"""Figure: how many handovers each searcher needs to find one worker's own optimum — the share
of runs that evaluated a cell at the worker's optimum (left) and within one point of it (right)
within n evaluations, per searcher, on log-scaled evaluations; the study's budgets marked.
Reads results/personalise/curves.csv and summary.csv."""

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


if __name__ == "__main__":
    main()
