"""Figures: (1) the postural score, REBA and RULA at the optimised vs the shortest-distance
location from each of the paper's five start points (the paper drew box plots; with five
starts and two or three score values their boxes are lines, so each start is a pair of dots
joined by a line); (2) the renders at both locations for each start point (a contact sheet made
by the baselines part, captioned here); (3) where the robot can hold the box over the
landscape's boundary, with the optimum and the best location it holds. Reads results/baselines/:
baselines.csv, renders/baseline_sheet.png, reachability.csv and reachability_summary.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import seaborn as sns
from common import (
    RESULTS,
    caption,
    integer_axis,
    n_text,
    plot_kind,
    read,
    save,
    share_of_grid,
)

LABELS = {"optimised": "optimised", "shortest_distance": "shortest distance"}
SCORES = ("paper_postural", "reba", "rula")


def main() -> None:
    table = read("baselines/baselines.csv")[["start_x", "start_y", "start_z", "method", *SCORES,
                                             "paper_postural_paper"]]
    # A start point is its coordinates; numbered in the order of the table (the paper's).
    table = table.assign(
        start=table.groupby(["start_x", "start_y", "start_z"], sort=False).ngroup() + 1)
    methods = list(LABELS)
    n = table.groupby("method").size()
    starts = table.drop_duplicates("start").set_index("start")
    # Dodged, not jittered: equal scores of different starts sit side by side, evenly.
    dodge = dict(zip(starts.index, np.linspace(-0.18, 0.18, len(starts)), strict=True))
    colours = dict(zip(starts.index, sns.color_palette("tab10", len(starts)), strict=True))
    fig, axes = plt.subplots(1, len(SCORES), figsize=(12, 3.9))
    for ax, score in zip(axes, SCORES, strict=True):
        wide = table.pivot(index="start", columns="method", values=score)[methods]
        shown = [*wide.to_numpy().ravel()]
        if plot_kind(table[score], table["method"]) == "box":  # many values: boxes inform
            ax.boxplot([wide[m].dropna() for m in methods], positions=range(len(methods)),
                       widths=0.5, showfliers=False, manage_ticks=False, zorder=1)
        for start, row in wide.iterrows():  # five starts: one line each
            x = np.arange(len(methods)) + dodge[start]
            ax.plot(x, row.to_numpy(dtype=float), "-o", color=colours[start], ms=5, lw=1,
                    label=f"start {start} ({starts.loc[start, 'start_x']:.2f}, "
                          f"{starts.loc[start, 'start_y']:.2f}, "
                          f"{starts.loc[start, 'start_z']:.2f}) m", zorder=3)
        if score == "paper_postural" and table["paper_postural_paper"].notna().any():
            paper = table.pivot(index="start", columns="method",
                                values="paper_postural_paper")[methods]
            for start, row in paper.iterrows():
                ax.scatter(np.arange(len(methods)) + dodge[start], row.to_numpy(dtype=float),
                           marker="x", color="#d62728", s=40, zorder=4,
                           label="the paper" if start == paper.index[0] else None)
            shown += [*paper.to_numpy().ravel()]
        integer_axis(ax, "y", [v for v in shown if v == v])
        ax.set_xticks(range(len(methods)), [LABELS[m] for m in methods])
        ax.set_xlim(-0.5, len(methods) - 0.5)
        ax.set_ylabel(score)
        ax.grid(axis="y", color="0.88", lw=0.5)
        ax.set_title(f"{score} ({n_text(n, 'start points')})", fontsize=10)
    handles, labels = axes[0].get_legend_handles_labels()  # the starts and the paper
    fig.legend(handles, labels, fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5),
               frameon=False)
    fig.suptitle("Optimised vs shortest-distance handover location, each start point scored at "
                 f"both ({n_text(n, 'start points')})")
    fig.tight_layout()
    caption(fig, "A line joins one start point's two locations; the dots of equal scores are "
                 "set side by side; x: the paper's score for the same start and location.")
    save(fig, "baselines_boxplot.png")
    renders(len(starts))


def renders(n_starts: int) -> None:
    """The baselines part's contact sheet of renders, with a caption stating N."""
    sheet = RESULTS / "baselines" / "renders" / "baseline_sheet.png"
    if not sheet.exists():
        return
    image = plt.imread(sheet)
    height, width = image.shape[:2]
    dpi = 130  # save()'s: one pixel of the sheet per pixel of the figure
    fig = plt.figure(figsize=(width / dpi, height / dpi))
    ax = fig.add_axes((0, 0, 1, 1))
    ax.imshow(image, interpolation="none")
    ax.set_axis_off()
    fig.text(0.5, 1.0, f"Renders at both locations (N = {n_starts} start points; left: "
                       "optimised, right: shortest distance)", ha="center", va="bottom",
             fontsize=9)
    save(fig, "baselines_renders.png")


def reachability_figure() -> None:
    reach = read("baselines/reachability.csv")
    summary = read("baselines/reachability_summary.csv").set_index("boundary")
    best = summary.iloc[0]
    grids = list(summary.index)
    fig, axes = plt.subplots(len(grids), 3, figsize=(12, 4.2 * len(grids)), squeeze=False)
    for row, name in zip(axes, grids, strict=True):
        grid = reach[reach["boundary"] == name]
        depths = sorted(grid["z"].round(6).unique())
        for ax, z in zip(row, [depths[0], depths[len(depths) // 2], depths[-1]], strict=True):
            layer = grid[grid["z"].round(6) == z]
            for held, style in ((1, {"marker": "o", "color": "#31a354", "label": "held"}),
                                (0, {"marker": "x", "color": "#d62728",
                                     "label": "not held"})):
                part = layer[layer["held"] == held]
                ax.scatter(part["x"], part["y"], s=18, **style)
            ax.scatter([best.optimum_x], [best.optimum_y], marker="*", s=160, color="#08519c",
                       label=f"optimum (z {best.optimum_z:.2f} m)", zorder=5)
            ax.scatter([best.held_x], [best.held_y], marker="+", s=160, color="black",
                       label=f"best held (z {best.held_z:.2f} m)", zorder=6)
            ax.set_title(f"{name} boundary, z = {z:.2f} m", fontsize=10)
            ax.set_xlabel("x [m] (worker's right +)")
        row[0].set_ylabel(f"{name}: held on {share_of_grid(summary.loc[name, 'held_fraction'])}"
                          "\ny [m] (height)")
    axes[0][0].legend(fontsize=8, loc="lower left")
    sizes = ", ".join(f"N = {int(r.locations):,} locations every {r.step_m * 100:g} cm "
                      f"({name})" for name, r in summary.iterrows())
    fig.suptitle(f"Where the robot holds the box for the handover (the twin gripping it): "
                 f"{sizes}\noptimum {best.optimum:g}, best held {best.held_optimum:g}")
    fig.tight_layout()
    save(fig, "robot_reachability.png")


if __name__ == "__main__":
    main()
    reachability_figure()
