"""Figure: the simulated participant study — each worker's scores at the location optimised
for the default worker, at its own optimum, and at the shortest-distance locations from the
two VR start points. Reads results/participants/participants.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from common import caption, integer_axis, read, save

KINDS = [("default-optimised", ""), ("own-optimised", ""), ("shortest-distance", "aligned"),
         ("shortest-distance", "offset-left")]
LABELS = ["optimised for default", "optimised for self", "shortest, aligned start",
          "shortest, start 1 m left"]
SCORES = ("paper_postural", "reba")


def main() -> None:
    table = read("participants/participants.csv")
    table["start"] = table["start"].fillna("")
    workers = list(dict.fromkeys(table["worker"]))
    # One column per (location, start): a worker's four scores side by side. An infeasible
    # location has no score (a gap, not a zero bar).
    wide = table.pivot_table(index="worker", columns=["location", "start"],
                             values=list(SCORES), aggfunc="first").reindex(workers)
    fig, axes = plt.subplots(1, len(SCORES), figsize=(12, 4))
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
        ax.set_xticks(np.arange(len(workers)), workers, rotation=20)
        ax.set_ylabel(score)
        ax.set_title(f"{score} by worker (N = {len(workers)} simulated workers)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=len(KINDS), fontsize=8,
               bbox_to_anchor=(0.5, 1.06), frameon=False)
    fig.tight_layout()
    caption(fig, f"N = {len(workers)} simulated workers, each scored at the four locations "
                 "(one bar each); a missing bar: the location is infeasible for that worker.")
    save(fig, "participants.png")


if __name__ == "__main__":
    main()
