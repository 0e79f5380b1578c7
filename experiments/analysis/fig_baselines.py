"""Figures: (1) the postural score and REBA at the optimised vs the shortest-distance location
over the paper's five start points (the paper's box plot); (2) the renders at both locations
for each start point (a contact sheet made by the baselines part); (3) where the robot can
hold the box over the landscape's boundary, with the optimum and the best location it holds.
Reads results/baselines/: baselines.csv, renders/baseline_sheet.png, reachability.csv and
reachability_summary.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
import seaborn as sns
from common import FIGURES, RESULTS, read, save

from ergohandover.io.atomic import atomic_write

LABELS = {"optimised": "optimised", "shortest_distance": "shortest distance"}


def main() -> None:
    table = read("baselines/baselines.csv")
    table = table.assign(method=table["method"].map(LABELS))
    n = table.groupby("method").size().iloc[0]
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.8))
    for ax, score in zip(axes, ("paper_postural", "reba", "rula"), strict=True):
        sns.boxplot(data=table, x="method", y=score, ax=ax, color="#c6dbef")
        sns.stripplot(data=table, x="method", y=score, ax=ax, color="#08519c", size=5,
                      jitter=False)  # jitter would come from numpy's global generator
        ax.set_title(f"{score} (N = {n} start points)")
        ax.set_xlabel("")
    paper = table.dropna(subset=["paper_postural_paper"])
    if len(paper):
        axes[0].scatter(paper["method"], paper["paper_postural_paper"], marker="x",
                        color="#d62728", zorder=5, label="the paper")
        axes[0].legend(fontsize=8)
    fig.suptitle("Optimised vs shortest-distance handover location")
    fig.tight_layout()
    save(fig, "baselines_boxplot.png")
    sheet = RESULTS / "baselines" / "renders" / "baseline_sheet.png"
    if sheet.exists():
        FIGURES.mkdir(parents=True, exist_ok=True)
        data = sheet.read_bytes()
        path = atomic_write(FIGURES / "baselines_renders.png", lambda h: h.write(data),
                            binary=True)
        print(f"wrote {path}")


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
        row[0].set_ylabel(f"{name}: {summary.loc[name, 'held_fraction']:.0%} held\n"
                          "y [m] (height)")
    axes[0][0].legend(fontsize=8, loc="lower left")
    fig.suptitle(f"Where the robot holds the box for the handover (the twin gripping it); "
                 f"optimum {best.optimum:g}, best held {best.held_optimum:g}")
    fig.tight_layout()
    save(fig, "robot_reachability.png")


if __name__ == "__main__":
    main()
    reachability_figure()
