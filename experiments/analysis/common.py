"""Shared by the figure scripts: paths, and reading results (figures never recompute)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pandas as pd

from ergohandover.io.atomic import atomic_write

ROOT = Path(__file__).resolve().parents[2]
# run_all --quick points the scripts at results/quick and paper_figs/quick.
RESULTS = Path(os.environ.get("ERGOHANDOVER_RESULTS", ROOT / "results"))
FIGURES = Path(os.environ.get("ERGOHANDOVER_FIGURES", ROOT / "paper_figs"))


def read(relative: str) -> pd.DataFrame:
    """A results CSV; a missing one ends the script with a one-line message."""
    path = RESULTS / relative
    if not path.exists():
        sys.exit(f"missing {path}: run python experiments/run_all.py first")
    return pd.read_csv(path, keep_default_na=False, na_values=[""])


def save(fig, name: str) -> Path:
    """Write a figure into paper_figs/ atomically and close it."""
    FIGURES.mkdir(parents=True, exist_ok=True)
    try:
        path = atomic_write(FIGURES / name, lambda h: fig.savefig(
            h, format="png", dpi=130, bbox_inches="tight"), binary=True)
    finally:
        plt.close(fig)
    print(f"wrote {path}")
    return path
