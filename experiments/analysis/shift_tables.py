"""The report's shift tables from results/shift/: each joint's endurance times beside the
published power law (``shift-reference``) and, per handover rate and hold, the posture's optimum
beside the locations best for the shift (``shift-locations``). Run by hand after the shift part
changes; the study's figure step never rewrites the documents."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
from common import RESULTS
from readme_blocks import rewrite


def reference_block(reference: pd.DataFrame) -> str:
    """The report's table: each joint's endurance times at each reference load [s]."""
    loads = sorted(reference["load"].unique())
    lines = ["| joint | never fails below | " + " | ".join(f"{load:.0%}: model / power law"
                                                          for load in loads) + " |",
             "|---|---|" + "---|" * len(loads)]
    for joint, table in reference.groupby("joint", sort=False):
        found = table.set_index("load")
        cells = [f"{found.loc[load, 'model_s']:,.0f} / {found.loc[load, 'power_law_s']:,.0f}"
                 for load in loads]
        lines.append(f"| {joint} | {table['never_fails_below'].iloc[0]:.1%} | "
                     f"{' | '.join(cells)} |")
    inside = int(reference["within_band"].sum())
    lines += ["", f"The model's time lies within the power law's 95 % band at {inside} of "
                  f"{len(reference)} joint-loads."]
    return "\n" + "\n".join(lines) + "\n"


def capacity(row) -> str:
    """A location's outcome over the shift: the lowest capacity at its end, or when it fails."""
    if np.isfinite(row["shift_failure_min"]):
        return f"fails after {row['shift_failure_min']:.0f} min"
    return f"{row['shift_capacity_end']:.0%} left"


def where(row) -> str:
    return f"({100 * row['x']:+.0f}, {100 * row['y']:.0f}, {100 * row['z']:.0f}) cm"


def locations_block(table: pd.DataFrame) -> str:
    """The report's table: per rate and hold, the posture's optimum and the locations best for
    the shift, each with the lowest capacity its joints keep and the paper score."""
    lines = ["| handovers a minute, hold | the posture's optimum | best for the shift at that "
             "score | best for the shift alone | LiFFT high-risk probability at the optimum |",
             "|---|---|---|---|---|"]
    for (rate, hold), rows in table.groupby(["rate_per_min", "hold_s"], sort=False):
        found = rows.set_index("location")
        cells = []
        for kind in ("posture-optimal", "best for the shift at the optimal score",
                     "best for the shift alone"):
            row = found.loc[kind]
            cells.append(f"{where(row)}, score {row['paper_postural']:.0f}: {capacity(row)}")
        cells.append(f"{found.loc['posture-optimal', 'lifft_high_risk']:.0%}")
        lines.append(f"| {rate:g}, {hold:g} s | {' | '.join(cells)} |")
    return "\n" + "\n".join(lines) + "\n"


def blocks(results: Path) -> dict[str, str]:
    return {"shift-reference": reference_block(
        pd.read_csv(results / "shift" / "reference.csv")),
            "shift-locations": locations_block(
        pd.read_csv(results / "shift" / "locations.csv"))}


def main() -> None:
    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
