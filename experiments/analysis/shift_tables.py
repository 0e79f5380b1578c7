"""The report's shift tables: each joint's endurance times beside the published power law
(``shift-reference``); per handover rate and hold, the default worker's posture optimum beside
the locations best for the shift and the shortest-distance ones (``shift-locations``), from
results/shift/; and the workforce's share that keeps enough of every joint's capacity
(``shift-workforce``, from results/accommodation/shift.csv). Also the shift's README headline
(:func:`shift_rows`). Run by hand after the shift or accommodation part changes; the study's
figure step never rewrites the documents."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
from common import RESULTS
from headline_types import Headline, pct
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


BASELINE = "shortest distance"
"""The locations read as the baseline (their names start with it): the robot's shortest-distance
location from each start."""


def baseline_cell(rows: pd.DataFrame) -> str:
    """The shortest-distance locations' scores and outcomes over the shift, as a range."""
    scores = rows["paper_postural"]
    score = (f"{scores.min():.0f}" if scores.min() == scores.max() else
             f"{scores.min():.0f}–{scores.max():.0f}")
    failing = rows["shift_failure_min"].dropna()
    failing = failing[np.isfinite(failing)]
    kept = rows["shift_capacity_end"].dropna()
    parts = []
    if len(failing):
        parts.append(f"{len(failing)} fail (after {failing.min():.0f}–{failing.max():.0f} min)"
                     if len(failing) > 1 else f"1 fails (after {failing.iloc[0]:.0f} min)")
    if len(kept):
        parts.append(f"{kept.min():.0%}–{kept.max():.0%} left" if len(kept) > 1 else
                     f"{kept.iloc[0]:.0%} left")
    return f"score {score}: {', '.join(parts)}"


def locations_block(table: pd.DataFrame) -> str:
    """The report's table: per rate and hold, the posture's optimum, the locations best for
    the shift and the shortest-distance locations, each with the lowest capacity its joints
    keep and the paper score."""
    lines = ["| handovers a minute, hold | the posture's optimum | best for the shift at that "
             "score | best for the shift alone | shortest distance (each start) | LiFFT "
             "high-risk probability at the optimum |", "|---|---|---|---|---|---|"]
    for (rate, hold), rows in table.groupby(["rate_per_min", "hold_s"], sort=False):
        found = rows.set_index("location")
        cells = []
        for kind in ("posture-optimal", "best for the shift at the optimal score",
                     "best for the shift alone"):
            row = found.loc[kind]
            cells.append(f"{where(row)}, score {row['paper_postural']:.0f}: {capacity(row)}")
        cells.append(baseline_cell(rows[rows["location"].str.startswith(BASELINE)]))
        cells.append(f"{found.loc['posture-optimal', 'lifft_high_risk']:.0%}")
        lines.append(f"| {rate:g}, {hold:g} s | {' | '.join(cells)} |")
    return "\n" + "\n".join(lines) + "\n"


def share_cell(row) -> str:
    return f"{row['kept_share']:.0%} ({row['kept_low']:.0%}–{row['kept_high']:.0%})"


def workforce_block(table: pd.DataFrame, zone: pd.DataFrame) -> str:
    """The report's table: per rate and hold, the share of the workforce keeping ``keep`` of
    every joint's capacity at the recommended location and at the shortest-distance ones, the
    share with a joint that fails, and the grid's cells that serve the stated share."""
    keep = table["keep"].iloc[0]
    n = int(table["workers"].iloc[0])
    lines = [f"| handovers a minute, hold | at the recommended location | at the shortest-distance"
             f" locations | a joint fails (recommended / shortest distance) | cells where "
             f"≥ {zone['share'].iloc[0]:.0%} keep it (of the grid's) |", "|---|---|---|---|---|"]
    zone = zone.set_index(["rate_per_min", "hold_s"])
    for (rate, hold), rows in table.groupby(["rate_per_min", "hold_s"], sort=False):
        found = rows.set_index("location")
        at = found.loc["nominal optimum"]
        base = rows[rows["location"].str.startswith(BASELINE)]
        zone_row = zone.loc[(rate, hold)]
        lines.append(
            f"| {rate:g}, {hold:g} s | {share_cell(at)} | {base['kept_share'].min():.0%}–"
            f"{base['kept_share'].max():.0%} | {at['fails_share']:.0%} / "
            f"{base['fails_share'].min():.0%}–{base['fails_share'].max():.0%} | "
            f"{int(zone_row['cells']):,} (best {zone_row['best_share']:.0%}) |")
    return (f"\nN = {n:,} workers; the share keeping at least {keep:.0%} of every joint's "
            "capacity at the shift's end, with its 95 % bootstrap interval over workers:\n\n"
            + "\n".join(lines) + "\n")


def headline_plan(table: pd.DataFrame) -> tuple[float, float]:
    """The shift the headline quotes: the most demanding studied (the fastest rate, then the
    longest hold), chosen by that rule before the results were read."""
    return max(zip(table["rate_per_min"], table["hold_s"], strict=True))


def shift_rows(results: Path) -> list[Headline]:
    """The README's row of the shift question: the default worker at the headline shift, and
    the workforce's share, each beside the shortest-distance locations."""
    table = pd.read_csv(results / "shift" / "locations.csv")
    workforce = pd.read_csv(results / "accommodation" / "shift.csv")
    rate, hold = headline_plan(table)
    rows = table[(table["rate_per_min"] == rate) & (table["hold_s"] == hold)]
    optimum = rows[rows["location"] == "posture-optimal"].iloc[0]
    base = rows[rows["location"].str.startswith(BASELINE)]
    crowd = workforce[(workforce["rate_per_min"] == rate) & (workforce["hold_s"] == hold)]
    at = crowd[crowd["location"] == "nominal optimum"].iloc[0]
    crowd_base = crowd[crowd["location"].str.startswith(BASELINE)]
    n = int(at["workers"])
    keep = at["keep"]
    claim = (f"{rate:g} handovers a minute held {hold:g} s for {optimum['hours']:g} h: at the "
             f"optimum the 50th-percentile man's weakest joint keeps {capacity(optimum)}; of "
             f"{n:,} workers {pct(at['kept_share'])} keep ≥ {keep:.0%} of every joint")
    reverses = []
    for (r, h), found in table.groupby(["rate_per_min", "hold_s"], sort=False):
        mine = found[found["location"] == "posture-optimal"]["shift_capacity_end"].fillna(-1)
        theirs = found[found["location"].str.startswith(BASELINE)]["shift_capacity_end"]
        if (theirs.fillna(-1) > mine.iloc[0] + 0.005).any():
            reverses.append(f"at {r:g} a minute, {h:g} s holds, a shortest-distance location "
                            "keeps more of the default worker's capacity")
    for (r, h), found in workforce.groupby(["rate_per_min", "hold_s"], sort=False):
        mine = found[found["location"] == "nominal optimum"].iloc[0]
        theirs = found[found["location"].str.startswith(BASELINE)]["kept_share"]
        if theirs.max() >= mine["kept_low"] and theirs.max() > 0:
            reverses.append(f"at {r:g} a minute, {h:g} s holds, a shortest-distance location "
                            f"serves the workforce as well ({pct(theirs.max())})")
    return [Headline(
        "shift", "over a shift", "the-shift-joint-fatigue-over-a-working-day", "not studied",
        claim, f"N = 1 worker; {n:,} workers for the share",
        f"one deterministic twin; share 95 % {pct(at['kept_low'])}–{pct(at['kept_high'])}",
        f"the shortest-distance locations: {baseline_cell(base)}; "
        f"{pct(crowd_base['kept_share'].min())}–{pct(crowd_base['kept_share'].max())} of "
        "workers", tuple(reverses),
        "at every rate and hold studied the optimum keeps at least as much as every "
        "shortest-distance location", ("shift/locations.csv", "accommodation/shift.csv"))]


def blocks(results: Path) -> dict[str, str]:
    shift, accommodation = results / "shift", results / "accommodation"
    return {"shift-reference": reference_block(pd.read_csv(shift / "reference.csv")),
            "shift-locations": locations_block(pd.read_csv(shift / "locations.csv")),
            "shift-workforce": workforce_block(pd.read_csv(accommodation / "shift.csv"),
                                               pd.read_csv(accommodation / "shift_zone.csv"))}


def main() -> None:
    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
