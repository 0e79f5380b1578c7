"""What the robustness question recorded, for the questions that read it (manikins,
accommodation)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd


def headline_locations(results: Path) -> pd.DataFrame:
    """The robustness part's headline locations (name, x, y, z), each once, in its order."""
    named = pd.read_csv(results / "robustness" / "locations.csv")
    return named[["location", "x", "y", "z"]].drop_duplicates("location").reset_index(drop=True)
