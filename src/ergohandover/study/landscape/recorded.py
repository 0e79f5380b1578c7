"""What the landscape question recorded, for tools and benchmarks that start from its
optimum."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd


def recorded_optimum(results: Path, score: str = "paper_postural") -> np.ndarray:
    """The optimum (x, y, z) [m] the part recorded in results/landscape/stats.csv, for tools
    and benchmarks that start from it (never a copy of the number in code)."""
    stats = pd.read_csv(results / "landscape" / "stats.csv").set_index("score")
    return stats.loc[score, ["best_x", "best_y", "best_z"]].to_numpy(dtype=float)
