"""Figure: the simulated participant study — each worker's scores at the location optimised
for the default worker, at its own optimum, and at the shortest-distance locations from the
two VR start points. Reads results/participants/participants.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from common import read, save

KINDS = [("default-optimised", ""), ("own-optimised", ""), ("shortest-distance", "aligned"),
         ("shortest-distance", "offset-left")]
LABELS = ["optimised for default", "optimised for self", "shortest, aligned start",
          "shortest, start 1 m left"]


def main() -> None:
    table = read("participants/participants.csv")
    table["start"] = table["start"].fillna("")
    workers = list(dict.fromkeys(table["worker"]))
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    width = 0.8 / len(KINDS)
    for ax, score in zip(axes, ("paper_postural", "reba"), strict=True):
        for k, ((location, start), label) in enumerate(zip(KINDS, LABELS, strict=True)):
            rows = table[(table["location"] == location) & (table["start"] == start)]
            values = [rows[rows["worker"] == w][score].iloc[0] for w in workers]
            heights = [np.nan if v == "" or v != v else float(v) for v in values]
            ax.bar(np.arange(len(workers)) + (k - 1.5) * width, heights, width, label=label)
        ax.set_xticks(np.arange(len(workers)), workers, rotation=20)
        ax.set_ylabel(score)
        ax.set_title(f"{score} by worker (N = {len(workers)} simulated workers)")
    axes[0].legend(fontsize=8, loc="lower left")
    save(fig, "participants.png")


if __name__ == "__main__":
    main()
