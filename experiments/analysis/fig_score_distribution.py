"""Figure: distribution of each score over the feasible points of the landscape (the paper's
"Distribution of Postural Score" figure): the share of the feasible points at each score value.
Reads results/landscape/{distribution,stats}.csv, whose ``fraction`` (distribution.csv) and
``fraction_at_min`` (stats.csv) are shares of the feasible points, and ``feasible_fraction``
the feasible points' share of the grid."""

from __future__ import annotations

import matplotlib.pyplot as plt
from common import (
    REBA_AB_NOTE,
    SCORE_WORDS,
    caption,
    integer_axis,
    percent,
    read,
    save,
    share_of_grid,
)
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
        # Upright, so that the labels of neighbouring small bars do not run into each other.
        ax.bar_label(bars, [percent(f, 2) for f in part["fraction"]], fontsize=7, padding=2,
                     rotation=90)
        # A value between the lowest and highest that no point takes has no bar: say so.
        values = set(part["value"])
        for empty in range(int(min(values)) + 1, int(max(values))):
            if empty not in values:
                ax.text(empty, 0, "none", rotation=90, ha="center", va="bottom", fontsize=7,
                        color="0.4")
        integer_axis(ax, "x", part["value"])
        ax.set_ylim(0, part["fraction"].max() * 1.3)  # room for the upright labels
        ax.yaxis.set_major_formatter(PercentFormatter(1.0, decimals=0, symbol=" %"))
        ax.set_title(SCORE_WORDS.get(score, score))
        ax.set_xlabel("score value")
        ax.set_ylabel("share of the feasible points")
    fig.suptitle(f"Scores over the landscape: N = {int(row['feasible']):,} feasible points "
                 f"({share_of_grid(row['feasible_fraction'], 3)}'s {int(row['points']):,} "
                 "points); the default worker (the 50th-percentile man) and box", fontsize=10)
    fig.tight_layout()
    caption(fig, "Each bar: the share of the feasible points at that score value (labelled; "
                 "'none': no point takes that value). Paper score: the paper's own postural "
                 f"score. {REBA_AB_NOTE}. A share of the grid counts all its points, infeasible "
                 "ones included.")
    save(fig, "score_distribution.png")


if __name__ == "__main__":
    main()
