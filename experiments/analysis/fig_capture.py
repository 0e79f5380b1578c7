"""Figure: how often a captured posture scores right — per keypoint format and published angle
error, the share of the twin's handover postures whose REBA, RULA and paper score come out as
one value equal to the error-free twin's (bars, 95 % intervals over postures), and the share
whose interval holds it (dots). Reads results/capture/scores.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from capture_tables import SCORE_NAMES, TITLES
from common import SCORE_WORDS, read, save


def main() -> None:
    table = read("capture/scores.csv")
    errors = sorted(table["angle_sd_deg"].unique())
    formats = list(dict.fromkeys(table["format"]))
    fig, axes = plt.subplots(1, len(SCORE_NAMES), figsize=(12, 3.8), sharey=True)
    width = 0.8 / len(errors)
    x = np.arange(len(formats))
    for ax, (score, name) in zip(axes, SCORE_NAMES.items(), strict=True):
        for k, sd in enumerate(errors):
            rows = table[(table["score"] == score) & (table["angle_sd_deg"] == sd)]
            rows = rows.set_index("format").loc[formats]
            at = x + (k - (len(errors) - 1) / 2) * width
            low = 100 * (rows["right"] - rows["right_ci_low"])
            high = 100 * (rows["right_ci_high"] - rows["right"])
            ax.bar(at, 100 * rows["right"], width, yerr=[low, high], capsize=2,
                   color=plt.cm.viridis(k / max(len(errors) - 1, 1)),
                   label=f"right, {sd:g}° error")
            ax.scatter(at, 100 * rows["holds"], color="black", s=10, zorder=3,
                       label="interval holds it" if k == 0 else None)
        ax.set_xticks(x, [TITLES[f] for f in formats], rotation=30, ha="right", fontsize=8)
        ax.set_title(SCORE_WORDS.get(score, name), fontsize=10)
        ax.set_ylim(0, 105)
    axes[0].set_ylabel("postures [%]")
    axes[-1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.suptitle(f"Scores from captured keypoints (N = {int(table['postures'].iloc[0]):,} of "
                 f"the twin's handover postures, {int(table['draws'].iloc[0])} measurements "
                 "each)", fontsize=10)
    save(fig, "capture_accuracy.png")


if __name__ == "__main__":
    main()
