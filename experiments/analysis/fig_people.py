"""Figures: the twin beside Kim et al.'s measured handovers. people_locations.png: where the
receivers' hands were at the transfer (sagittal and frontal planes, each dot a handover) beside
the one-handed optimum of the median receiver's twin for each score, and the distribution of
the receivers' measured REBA at the transfer (the interval's ends where ZED BODY_34 cannot see a
column). people_angles.png: per angle, the twin's predicted angle against the receiver's
measured one, with the identity line. Reads results/people/ only."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from common import caption, integer_axis, read, save
from people_tables import ANGLE_NAMES, CAVEAT, SCORE_NAMES

MARKERS = {"reba": "*", "rula": "P", "paper_postural": "D"}


def locations() -> None:
    table = read("people/handovers.csv")
    advice = read("people/recommendation.csv")
    n = len(table)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
    planes = ((axes[0], "hand_forward_m", "forward of the feet [m]", "optimum_z"),
              (axes[1], "hand_side_m", "to the receiving hand's side of the feet [m]",
               "optimum_x"))
    for ax, column, label, key in planes:
        ax.scatter(table[column], table["hand_height_m"], s=6, alpha=0.35, color="tab:blue",
                   label="receivers' hands at the transfer")
        for row in advice.itertuples():
            ax.scatter(getattr(row, key), row.optimum_y, marker=MARKERS[row.score], s=90,
                       color="tab:red", edgecolor="black", zorder=3,
                       label=f"twin's optimum, {SCORE_NAMES[row.score]} ({row.optimum})")
        ax.set_xlabel(label)
        ax.set_ylabel("height above the floor [m]")
    axes[0].set_title(f"Sagittal plane (N = {n:,} handovers)", fontsize=10)
    axes[1].set_title("Frontal plane", fontsize=10)
    axes[1].legend(fontsize=7, loc="lower right")
    low, high = table["people_reba_lo"], table["people_reba_hi"]
    values = np.arange(1, 16)
    width = 0.4
    axes[2].bar(values - width / 2, [(low == v).sum() for v in values], width,
                label="lowest REBA the unseen columns allow")
    axes[2].bar(values + width / 2, [(high == v).sum() for v in values], width,
                label="highest")
    axes[2].set_xlim(0.3, max(high.max(), 6) + 0.7)
    integer_axis(axes[2], "x", values)
    axes[2].set_xlabel("REBA at the transfer")
    axes[2].set_ylabel("handovers")
    axes[2].set_title(f"Receivers' measured REBA (N = {n:,})", fontsize=10)
    axes[2].legend(fontsize=7)
    fig.tight_layout()
    caption(fig, "Each dot a receiver's hand point at the transfer, measured by a ZED2i "
            "(BODY_34); the twin's optimum for the same one-handed task, sized as the median "
            f"receiver. {CAVEAT}")
    save(fig, "people_locations.png")


def angles() -> None:
    table = read("people/handovers.csv")
    held = table[table["split"] != "train"]
    fig, axes = plt.subplots(2, 3, figsize=(11, 7))
    for ax, (angle, name) in zip(axes.ravel(), ANGLE_NAMES.items(), strict=True):
        measured, twin = held[f"measured_{angle}"], held[f"twin_{angle}"]
        fitted = held[f"fitted_{angle}"]
        ax.scatter(measured, twin, s=5, alpha=0.4, label="default twin")
        ax.scatter(measured, fitted, s=5, alpha=0.4, label="fitted twin")
        both = np.concatenate([measured, twin, fitted])
        span = [np.nanmin(both) - 5, np.nanmax(both) + 5]
        ax.plot(span, span, color="black", linewidth=0.8, label="identity")
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("receiver, measured [deg]", fontsize=8)
        ax.set_ylabel("twin, predicted [deg]", fontsize=8)
    axes[0, 0].legend(fontsize=7, markerscale=3)
    fig.suptitle(f"The twin's predicted angles against the receivers' (N = {len(held):,} "
                 "handovers not used by the fit)", fontsize=10)
    fig.tight_layout()
    caption(fig, "Each dot a handover: the twin sized to that receiver, its grip where the "
            "receiver's hand was; both sides read through the same ZED BODY_34 keypoints, "
            "trunk, neck and knee from each side's standing neutral. Held out, the twin alone "
            f"predicts worse than the receivers' mean angle (results/people/skill.csv). {CAVEAT}")
    save(fig, "people_angles.png")


def main() -> None:
    locations()
    angles()


if __name__ == "__main__":
    main()
