"""Figures: (1) the minimum score of every run, per agent and cap (the paper's box plot of 10
Q-learning runs at 2 and 5 minutes, with DQN and the search baselines beside it), against the
landscape's global minimum; (2) best-so-far score against time, every run. Reads
results/learning/{runs,truth}.csv and results/learning/traces/."""

from __future__ import annotations

import matplotlib.pyplot as plt
import pandas as pd
import seaborn as sns
from common import RESULTS, read, save


def boxplot(runs: pd.DataFrame, truth: pd.Series) -> None:
    runs = runs.assign(run=runs["agent"] + " " + runs["cap_s"].map("{:g} s".format))
    order = list(dict.fromkeys(runs["run"]))
    fig, ax = plt.subplots(figsize=(max(6, 1.1 * len(order)), 4))
    sns.boxplot(data=runs, x="run", y="best_score", order=order, ax=ax, color="#9ecae1")
    # No jitter: seaborn draws it from numpy's global generator, which would make the figure
    # differ between rebuilds of the same results.
    sns.stripplot(data=runs, x="run", y="best_score", order=order, ax=ax, color="#08519c",
                  size=4, jitter=False)
    ax.axhline(truth["global_min"], color="#d62728", ls="--",
               label=f"global minimum ({truth['global_min']:g}, exhaustive)")
    n = runs.groupby("run").size()
    ax.set_xticks(range(len(order)), [f"{r}\nN = {n[r]}" for r in order], fontsize=8)
    ax.set_xlabel("")
    ax.set_ylabel(f"minimum {truth['objective']} of the run")
    ax.set_title("Minimum score per run, by agent and time cap")
    ax.legend(fontsize=8)
    save(fig, "learning_min_score.png")


def best_so_far(runs: pd.DataFrame, truth: pd.Series) -> None:
    fig, ax = plt.subplots(figsize=(7, 4))
    colours = dict(zip(dict.fromkeys(runs["agent"]), sns.color_palette(n_colors=8),
                       strict=False))
    seen = set()
    for _, r in runs.iterrows():
        tag = f"{r['agent']}_{r['objective']}_{r['temperature']}_cap{r['cap_s']}_seed{r['seed']}"
        trace = pd.read_csv(RESULTS / "learning" / "traces" / f"{tag}.csv")
        trace = trace[trace["best_score"] < float("inf")]
        if trace.empty:
            continue
        label = None if r["agent"] in seen else r["agent"]
        seen.add(r["agent"])
        ax.step(trace["time_s"].clip(lower=1e-4), trace["best_score"], where="post",
                color=colours[r["agent"]], alpha=0.6, label=label)
    ax.axhline(truth["global_min"], color="#d62728", ls="--", label="global minimum")
    ax.set_xscale("log")
    ax.set_xlabel("wall time [s] (log)")
    ax.set_ylabel(f"best {truth['objective']} so far")
    ax.set_title(f"Best-so-far score against time, N = {len(runs)} runs")
    ax.legend(fontsize=8)
    save(fig, "learning_best_so_far.png")


def main() -> None:
    runs, truth = read("learning/runs.csv"), read("learning/truth.csv").iloc[0]
    boxplot(runs, truth)
    best_so_far(runs, truth)


if __name__ == "__main__":
    main()
