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


def span(low: str, high: str) -> str:
    """``low–high``, or one of them where they read the same."""
    return low if low == high else f"{low}–{high}"


def baseline_cell(rows: pd.DataFrame) -> str:
    """The shortest-distance locations' scores and outcomes over the shift, as a range."""
    scores = rows["paper_postural"]
    score = span(f"{scores.min():.0f}", f"{scores.max():.0f}")
    failing = rows["shift_failure_min"].dropna()
    failing = failing[np.isfinite(failing)]
    kept = rows["shift_capacity_end"].dropna()
    parts = []
    if len(failing):
        parts.append(f"{len(failing)} fail (after {failing.min():.0f}–{failing.max():.0f} min)"
                     if len(failing) > 1 else f"1 fails (after {failing.iloc[0]:.0f} min)")
    if len(kept):
        parts.append(f"{span(f'{kept.min():.0%}', f'{kept.max():.0%}')} left")
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
    interval = span(f"{row['kept_low']:.0%}", f"{row['kept_high']:.0%}")
    return f"{row['kept_share']:.0%}" + ("" if interval == f"{row['kept_share']:.0%}" else
                                         f" ({interval})")


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
        kept, fails = (span(f"{base[c].min():.0%}", f"{base[c].max():.0%}")
                       for c in ("kept_share", "fails_share"))
        lines.append(
            f"| {rate:g}, {hold:g} s | {share_cell(at)} | {kept} | {at['fails_share']:.0%} / "
            f"{fails} | {int(zone_row['cells']):,} (best {zone_row['best_share']:.0%}) |")
    return (f"\nN = {n:,} workers; the share keeping at least {keep:.0%} of every joint's "
            "capacity at the shift's end, with its 95 % bootstrap interval over workers:\n\n"
            + "\n".join(lines) + "\n")


def demanding(plans) -> list[tuple[float, float]]:
    """Shifts (rate, hold) from the most demanding down: the most seconds held a minute, then
    the fastest rate."""
    return sorted(set(plans), key=lambda p: (p[0] * p[1], p[0]), reverse=True)


def left(row) -> str:
    """What a location leaves the weakest joint at the shift's end, or when one fails."""
    if np.isfinite(row["shift_failure_min"]):
        return f"a joint fails after {row['shift_failure_min']:.0f} min"
    return f"{pct(row['shift_capacity_end'])} left"


def shift_rows(results: Path) -> list[Headline]:
    """The README's row of the shift question: over every shift studied, the default worker's
    weakest joint at the posture's optimum beside the shortest-distance locations (the
    figures quoted at the most demanding shift), and the workforce's share at the most
    demanding shift the recommended location still serves anyone at."""
    table = pd.read_csv(results / "shift" / "locations.csv")
    workforce = pd.read_csv(results / "accommodation" / "shift.csv")
    kept = table.assign(left=table["shift_capacity_end"].fillna(-1.0))
    base = kept["location"].str.startswith(BASELINE)
    mine = kept[kept["location"] == "posture-optimal"].set_index(["rate_per_min", "hold_s"])
    theirs = kept[base].groupby(["rate_per_min", "hold_s"])["left"].max()
    plans = demanding(mine.index)
    rate, hold = plans[0]
    at_worst = kept[base & (kept["rate_per_min"] == rate) & (kept["hold_s"] == hold)]
    crowd = workforce.set_index(["rate_per_min", "hold_s"])
    served = [p for p in demanding(crowd.index) if crowd.loc[p].set_index("location").loc[
        "nominal optimum", "kept_share"] > 0]
    r2, h2 = served[0] if served else plans[0]
    here = crowd.loc[(r2, h2)].set_index("location")
    at, others = here.loc["nominal optimum"], here[here.index.str.startswith(BASELINE)]
    n = int(at["workers"])
    holds = " or ".join(f"{h:g}" for h in sorted({p[1] for p in plans}))
    at_least = "≥" if (mine["left"] >= theirs - 0.005).all() else "not always ≥"
    claim = (f"{mine['hours'].iloc[0]:g} h at {min(p[0] for p in plans):g}–"
             f"{max(p[0] for p in plans):g} handovers/min held {holds} s: the optimum "
             f"leaves the p50 man's weakest joint {at_least} shortest distance's "
             f"({left(mine.loc[(rate, hold)])} at {rate:g}/min, {hold:g} s); "
             f"{pct(at['kept_share'])} of workers keep {pct(at['keep'])} at {r2:g}/min, {h2:g} s")
    reverses = [f"at {r:g} a minute held {h:g} s a shortest-distance location leaves the "
                "default worker more" for r, h in plans if theirs[(r, h)] > mine.loc[(r, h),
                                                                                  "left"] + 0.005]
    for r, h in demanding(crowd.index):
        shares = crowd.loc[(r, h)].set_index("location")["kept_share"]
        best_other = shares[shares.index.str.startswith(BASELINE)].max()
        if best_other >= shares["nominal optimum"]:
            reverses.append(f"for the workforce at {r:g} a minute held {h:g} s a "
                            f"shortest-distance location keeps as many ({pct(best_other)})")
    fails = at_worst["shift_failure_min"]
    failing = fails[np.isfinite(fails)]
    worst = (f"{len(failing)} of {len(at_worst)} fail a joint in "
             f"{failing.min():.0f}–{failing.max():.0f} min at {rate:g} a minute held {hold:g} s"
             if len(failing) else f"{capacity(at_worst.iloc[0])} at {rate:g} a minute")
    return [Headline(
        "shift", "over a shift", "the-shift-joint-fatigue-over-a-working-day", "not studied",
        claim, f"N = 1 worker, {len(plans)} shifts; {n:,} workers",
        f"one twin; share 95 % {pct(at['kept_low'])}–{pct(at['kept_high'])}",
        f"the shortest-distance locations: {worst}; {pct(others['kept_share'].max())} of the "
        f"workers keep {pct(at['keep'])} at {r2:g} a minute held {h2:g} s",
        tuple(reverses), "at every shift studied the optimum leaves at least as much",
        ("shift/locations.csv", "accommodation/shift.csv"))]


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
