"""Figures: (1) the postural score and REBA at the optimised vs the shortest-distance location
over the paper's five start points (the paper's box plot); (2) the renders at both locations
for each start point (a contact sheet made by the baselines part). Reads
results/baselines/baselines.csv and results/baselines/renders/baseline_sheet.png."""

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


if __name__ == "__main__":
    main()
