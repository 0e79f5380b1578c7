"""Figure: distribution of each score over the feasible points of the landscape (the paper's
"Distribution of Postural Score" figure): the share of the feasible points at each score value.
Reads results/landscape/{distribution,stats}.csv, whose ``fraction`` (distribution.csv) and
``fraction_at_min`` (stats.csv) are shares of the feasible points, and ``feasible_fraction``
the feasible points' share of the grid."""

from __future__ import annotations

import matplotlib.pyplot as plt
from common import caption, integer_axis, percent, read, save, share_of_grid
from matplotlib.ticker import PercentFormatter


def main() -> None:
    dist, stats = read("landscape/distribution.csv"), read("landscape/stats.csv")
    row = stats.iloc[0]
    scores = list(dict.fromkeys(dist["score"]))
    fig, axes = plt.subplots(1, len(scores), figsize=(4 * len(scores), 3.6), squeeze=False)
    for ax, score in zip(axes[0], scores, strict=True):
        part = dist[dist["score"] == score]
        bars = ax.bar(part["value"], part["fraction"], width=0.8, color="#3b75af")
        # Two significant digits: the smallest shares (a few thousandths of a percent) too.
        ax.bar_label(bars, [percent(f, 2) for f in part["fraction"]], fontsize=6.5, padding=1)
        integer_axis(ax, "x", part["value"])
        ax.set_ylim(0, part["fraction"].max() * 1.15)
        ax.yaxis.set_major_formatter(PercentFormatter(1.0, decimals=0, symbol=" %"))
        ax.set_title(score)
        ax.set_xlabel("score")
        ax.set_ylabel("share of the feasible points")
    fig.suptitle(f"Scores over the landscape: N = {int(row['feasible']):,} feasible points "
                 f"({share_of_grid(row['feasible_fraction'], 3)}'s {int(row['points']):,} "
                 "points); default worker and box", fontsize=10)
    fig.tight_layout()
    caption(fig, "Each bar: the share of the feasible points at that score value (labelled). "
                 "A share of the grid counts all its points, infeasible ones included.")
    save(fig, "score_distribution.png")


if __name__ == "__main__":
    main()
