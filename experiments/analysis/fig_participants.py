"""Figure: the simulated participant study — each worker's scores at the location optimised
for the default worker, at its own optimum, and at the shortest-distance locations from the
two VR start points, the workers in order of stature, smallest first. Reads
results/participants/participants.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from common import SCORE_WORDS, caption, integer_axis, read, save, worker_words

KINDS = [("default-optimised", ""), ("own-optimised", ""), ("shortest-distance", "aligned"),
         ("shortest-distance", "offset-left")]
LABELS = ["optimised for the default worker", "the worker's own optimum",
          "shortest distance, aligned start", "shortest distance, start 1 m left"]
SCORES = ("paper_postural", "reba")


def tick(worker: str, stature: float) -> str:
    """``"woman\n5th percentile\n1.52 m"``: three short lines, which neighbours do not run
    into."""
    percentile, sex = worker_words(worker).rsplit(" ", 1)
    return f"{sex}\n{percentile.replace('-', ' ')}\n{stature:.2f} m"


def main() -> None:
    table = read("participants/participants.csv")
    table["start"] = table["start"].fillna("")
    # Smallest first: the scores change with body size, and the table's order is not by it.
    statures = table.groupby("worker")["stature_m"].first().sort_values(kind="stable")
    workers = list(statures.index)
    # One column per (location, start): a worker's four scores side by side. An infeasible
    # location has no score (a gap, not a zero bar).
    wide = table.pivot_table(index="worker", columns=["location", "start"],
                             values=list(SCORES), aggfunc="first").reindex(workers)
    fig, axes = plt.subplots(1, len(SCORES), figsize=(14, 4.2))
    width = 0.8 / len(KINDS)
    for ax, score in zip(axes, SCORES, strict=True):
        heights = wide[score].reindex(columns=pd.MultiIndex.from_tuples(KINDS))
        heights = heights.apply(pd.to_numeric, errors="coerce")
        for k, (kind, label) in enumerate(zip(KINDS, LABELS, strict=True)):
            ax.bar(np.arange(len(workers)) + (k - 1.5) * width, heights[kind], width,
                   label=label)
        integer_axis(ax, "y")
        ax.set_ylim(0, np.nanmax(heights.to_numpy()) + 0.6)
        ax.grid(axis="y", color="0.88", lw=0.5)
        ax.set_axisbelow(True)
        ax.set_xticks(np.arange(len(workers)), [tick(w, statures[w]) for w in workers],
                      fontsize=8)
        ax.set_ylabel(SCORE_WORDS.get(score, score))
        ax.set_title(f"{SCORE_WORDS.get(score, score)} by worker, smallest first "
                     f"(N = {len(workers)} simulated workers)", fontsize=10)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=len(KINDS), fontsize=8,
               bbox_to_anchor=(0.5, 1.06), frameon=False)
    fig.tight_layout()
    caption(fig, f"N = {len(workers)} simulated workers (percentiles of stature, with their "
                 "stature), each scored at the four locations (one bar each): the location "
                 "optimised for the default worker (the 50th-percentile man), the worker's own "
                 "optimum, and the shortest-distance locations from the two VR start points "
                 "(aligned with the worker, and 1 m to the left). A missing bar: the location is "
                 "infeasible for that worker.")
    save(fig, "participants.png")


if __name__ == "__main__":
    main()
