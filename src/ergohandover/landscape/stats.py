"""Statistics of a landscape: score distributions over feasible points, the minimum and where
it is reached (count, bounding box, the most symmetric minimiser), the feasible fraction."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..ergonomics import OBJECTIVES
from ..io.atomic import atomic_write, atomic_write_csv
from .cache import Landscape, LandscapeError


def most_symmetric(points: np.ndarray) -> int:
    """Index of the most symmetric of (n, 3) locations: smallest |x|; among those, nearest to
    their centroid; then the first."""
    lateral = np.abs(points[:, 0])
    best = np.flatnonzero(np.isclose(lateral, lateral.min(), rtol=0, atol=1e-9))
    centre = points[best].mean(axis=0)
    return int(best[np.argmin(np.linalg.norm(points[best] - centre, axis=1))])


def minimum(landscape: Landscape, score: str) -> float:
    """The landscape's lowest ``score`` over its feasible points."""
    return float(landscape.arrays[score][landscape.feasible].min())


def at_minimum(landscape: Landscape, score: str) -> np.ndarray:
    """(N,) bool: the feasible points at the score's minimum."""
    return landscape.feasible & (landscape.arrays[score] == minimum(landscape, score))


def minimisers(landscape: Landscape, score: str) -> np.ndarray:
    """Flat indices of the feasible points at the score's minimum."""
    return np.flatnonzero(at_minimum(landscape, score))


def optimum(landscape: Landscape, score: str = "paper_postural") -> tuple[np.ndarray, np.ndarray]:
    """The best location of a landscape for ``score``: the study's one rule.

    Returns:
        The flat indices of every feasible point at the minimum, and the most symmetric of
        them (:func:`most_symmetric`), (3,) worker frame [m].
    """
    if score not in landscape.arrays:
        raise LandscapeError(f"score = {score!r} is not in the landscape (has "
                             f"{', '.join(sorted(landscape.arrays))})")
    if not landscape.feasible.any():
        raise LandscapeError("the landscape has no feasible point")
    cells = minimisers(landscape, score)
    points = landscape.grid.coordinates(cells)
    return cells, points[most_symmetric(points)]


@dataclass(frozen=True)
class Exhaustive:
    """The ground truth of a landscape for one objective.

    Attributes:
        score: the lowest feasible score.
        cells: flat indices of every cell at it.
        location: the most symmetric of them (x, y, z) [m].
        fraction: share of the feasible cells at the minimum.
    """

    score: float
    cells: np.ndarray
    location: tuple[float, float, float]
    fraction: float


def exhaustive(landscape: Landscape, objective: str = "paper_postural") -> Exhaustive:
    """The landscape's minimum of ``objective`` (every cell was evaluated by the sweep): what a
    search is measured against."""
    cells, best = optimum(landscape, objective)
    return Exhaustive(float(landscape.arrays[objective][cells[0]]), cells,
                      tuple(float(v) for v in best), len(cells) / int(landscape.feasible.sum()))


def statistics(landscape: Landscape) -> pd.DataFrame:
    """One row per score: feasible count and fraction, minimum, how many points reach it and
    where (bounding box, most symmetric minimiser), worker frame [m]."""
    feasible = landscape.feasible
    if not feasible.any():
        raise LandscapeError("the landscape has no feasible point")
    rows = []
    for score in OBJECTIVES:
        at_min = minimisers(landscape, score)
        points = landscape.grid.coordinates(at_min)
        best = points[most_symmetric(points)]
        rows.append({
            "score": score, "points": landscape.grid.size, "feasible": int(feasible.sum()),
            "feasible_fraction": feasible.mean(),
            "min": int(landscape.arrays[score][at_min[0]]), "n_at_min": len(at_min),
            "fraction_at_min": len(at_min) / feasible.sum(),
            **{f"{a}_{e}": f(points[:, k]) for k, a in enumerate("xyz")
               for e, f in (("min", np.min), ("max", np.max))},
            "best_x": best[0], "best_y": best[1], "best_z": best[2],
        })
    return pd.DataFrame(rows)


def distributions(landscape: Landscape) -> pd.DataFrame:
    """Counts and fractions of each score value over the feasible points."""
    feasible = landscape.feasible
    frames = []
    for score in OBJECTIVES:
        values, counts = np.unique(landscape.arrays[score][feasible], return_counts=True)
        frames.append(pd.DataFrame({"score": score, "value": values.astype(int),
                                    "count": counts, "fraction": counts / feasible.sum()}))
    return pd.concat(frames, ignore_index=True)


def plot_distributions(dist: pd.DataFrame, title: str, path: Path) -> Path:
    """The paper's 'distribution of postural score' figure, one panel per score."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import seaborn as sns

    scores = list(dict.fromkeys(dist["score"]))
    fig, axes = plt.subplots(1, len(scores), figsize=(4 * len(scores), 3.6), squeeze=False)
    for ax, score in zip(axes[0], scores, strict=True):
        part = dist[dist["score"] == score]
        sns.barplot(data=part, x="value", y="fraction", ax=ax, color="#3b75af")
        ax.set_title(score)
        ax.set_xlabel("score")
        ax.set_ylabel("fraction of feasible points")
        for patch, fraction in zip(ax.patches, part["fraction"], strict=False):
            ax.annotate(f"{fraction:.1%}" if fraction >= 0.001 else f"{fraction:.4%}",
                        (patch.get_x() + patch.get_width() / 2, patch.get_height()),
                        ha="center", va="bottom", fontsize=7)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    try:
        return atomic_write(path, lambda h: fig.savefig(h, format="png", dpi=130), binary=True)
    finally:
        plt.close(fig)


def write_statistics(landscape: Landscape, stem: Path) -> tuple[pd.DataFrame, list[Path]]:
    """Write ``<stem>_stats.csv``, ``<stem>_distribution.csv`` and ``<stem>_distribution.png``."""
    stats, dist = statistics(landscape), distributions(landscape)
    paths = [atomic_write_csv(stats, stem.with_name(stem.name + "_stats.csv")),
             atomic_write_csv(dist, stem.with_name(stem.name + "_distribution.csv"))]
    title = (f"{landscape.grid.describe()}; N = {int(landscape.feasible.sum()):,} feasible "
             f"points")
    paths.append(plot_distributions(dist, title,
                                    stem.with_name(stem.name + "_distribution.png")))
    return stats, paths
