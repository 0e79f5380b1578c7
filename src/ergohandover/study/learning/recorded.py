"""What the learning question recorded, for the questions that read it (baselines)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ...errors import ConfigError
from .config import LearnedLocation


def learned_location(results: Path, spec: LearnedLocation) -> pd.Series:
    """The row of results/learning/found.csv named by ``spec`` (target, agent, budget)."""
    found = pd.read_csv(results / "learning" / "found.csv")
    row = found[(found["target"] == spec.target) & (found["agent"] == spec.agent)
                & (found["budget"] == spec.budget)]
    if row.empty:
        raise ConfigError(f"baselines.location = {spec} names no row of "
                          f"{results / 'learning' / 'found.csv'}")
    return row.iloc[0]
