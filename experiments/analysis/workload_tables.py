"""The practitioner's blocks, from results/manikins/ and results/accommodation/ only: the README's
headline cell on the workforce's accommodation zone, the report's table of the zone at each
headline location and the table of the four manikins at the headline locations.
``python workload_tables.py`` rewrites them after the study."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
from headlines import exact_interval, pct
from readme_blocks import rewrite

from ergohandover.workload.flags import LIFTING_INDEX_SCOPE, flag_column

RECOMMENDED = "nominal optimum"
MANIKIN_LOCATIONS = ("nominal optimum", "robust optimum", "learned", "practice",
                     "shortest distance, start 1", "shortest distance, start 4")
"""The headline locations the manikins table shows (the rest are in results/manikins/)."""


def _read(results: Path) -> tuple[pd.DataFrame, pd.DataFrame, dict]:
    folder = results / "accommodation"
    return (pd.read_csv(folder / "locations.csv"), pd.read_csv(folder / "zone.csv").set_index(
        "kind"), json.loads((folder / "manifest.json").read_text())["config"]["accommodation"])


def percent(value: float) -> str:
    return f"{100 * value:.0f} %"


def interval(row, kind: str) -> str:
    """A share with its interval: for the error-free share (each worker suited or not) the
    exact binomial one, never degenerate at 0 or 100 %; for the measured share (the mean
    chance that one measurement agrees) the bootstrap one over workers."""
    if kind == "exact":
        n = int(row["workers"])
        low, high = exact_interval(round(row["exact_share"] * n), n)
        return f"{pct(row['exact_share'])} ({pct(low)}–{pct(high)})"
    return f"{percent(row[f'{kind}_share'])} ({100 * row[f'{kind}_low']:.0f}–" \
           f"{100 * row[f'{kind}_high']:.0f} %)"


def box_text(zone_row, part: dict) -> str:
    """The largest box of the zone, as the README states it."""
    if pd.isna(zone_row.get("box_cells")):
        return ""
    ranges = ", ".join(f"{a} {zone_row[f'box_{a}_min']:+.2f} to {zone_row[f'box_{a}_max']:+.2f}"
                       for a in "xyz")
    return f"; the largest box of them holds {int(zone_row['box_cells']):,} points ({ranges} m)"


def measured_clause(zone: pd.DataFrame) -> str:
    """What measuring does to the zone: the reversing condition of the headline."""
    measured = zone.loc["measured"]
    if int(measured["cells"]) == 0:
        return (f"as one measurement under the IMU-like error model judges them, no point "
                f"serves {percent(measured['share'])} (the best {percent(measured['best_share'])})")
    return (f"as one measurement under the IMU-like error model judges them, "
            f"{int(measured['cells']):,} points serve {percent(measured['share'])}")


def headline(results: Path) -> str:
    at, zone, part = _read(results)
    rec = at[at["location"] == RECOMMENDED].iloc[0]
    exact = zone.loc["exact"]
    return (f"of N = {int(rec['workers']):,} workers drawn from the survey's model, REBA ≤ "
            f"{part['reba_max']} and RULA ≤ {part['rula_max']} hold at the recommended location "
            f"error-free for {interval(rec, 'exact')} (exact 95 % interval); one measurement "
            "under an IMU-like error model (4 of its 15 SDs from Schall et al. 2016; the other "
            "SDs, every correlation and the zero biases assumed) "
            + (f"agrees with that for {interval(rec, 'measured')} of measurements, "
               f"misclassifying {percent(1 - rec['measured_share'])}"
               if rec["exact_share"] == 1 else
               f"passes a worker in {interval(rec, 'measured')} of measurements")
            + " (95 % bootstrap interval over workers); "
            "error-free, "
            f"{int(exact['cells']):,} points of a {100 * part['step']:g} cm grid serve "
            f"{percent(exact['share'])} of them{box_text(exact, part)}; "
            f"{measured_clause(zone)}")


def accommodation_table(results: Path) -> list[str]:
    at, _, _ = _read(results)
    lines = ["| location | x, y, z [m] | can take the box | suited, error-free (exact 95 %) | "
             "one measurement passes (bootstrap 95 %) |", "|---|---|---|---|---|"]
    for _, row in at.iterrows():
        lines.append(f"| {row['location']} | {row['x']:.3f}, {row['y']:.3f}, {row['z']:.3f} | "
                     f"{percent(row['feasible_share'])} | {interval(row, 'exact')} | "
                     f"{interval(row, 'measured')} |")
    return lines


def manikins_table(results: Path) -> list[str]:
    table = pd.read_csv(results / "manikins" / "manikins.csv")
    table["flags"] = flag_column(table)
    lines = [f"The lifting index is the same for every manikin at a location: "
             f"{LIFTING_INDEX_SCOPE}. Flags name every action limit exceeded and every "
             "figure within 1 cm of a cut-off of the lifting equation.", "",
             "| location | manikin | REBA | RULA | OWAS | paper | lifting index, location only "
             "(RWL kg) | L5/S1 compression [N] | % capable (back) | flags |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for name in MANIKIN_LOCATIONS:
        for _, row in table[table["location"] == name].iterrows():
            if not row["feasible"]:
                lines.append(f"| {name} | {row['manikin']} | – | – | – | – | – | – | "
                             f"cannot take it ({row['reason']}) | |")
                continue
            lines.append(
                f"| {name} | {row['manikin']} | {int(row['reba'])} | {int(row['rula'])} | "
                f"{int(row['owas'])} ({int(row['owas_code'])}) | {int(row['paper_postural'])} | "
                f"{row['niosh_li']:.2f} ({row['niosh_rwl_kg']:.1f}) | "
                f"{row['back_compression_n']:,.0f} | {row['back_capable_pct']:.1f} | "
                f"{row['flags']} |")
    hidden = table[~table["location"].isin(MANIKIN_LOCATIONS) & (table["flags"] != "")]
    if len(hidden):
        listed = "; ".join(f"{location} ({', '.join(rows['manikin'])}): {flag}"
                           for (location, flag), rows in hidden.groupby(["location", "flags"],
                                                                         sort=False))
        lines += ["", f"Flags at the other headline locations (`manikins.csv`): {listed}."]
    return lines


def blocks(results: Path) -> dict[str, str]:
    """Each generated block's text, from ``results`` only."""
    return {"accommodation-headline": headline(results),
            "accommodation-table": "\n" + "\n".join(accommodation_table(results)) + "\n",
            "manikins-table": "\n" + "\n".join(manikins_table(results)) + "\n"}


def main() -> None:
    """Rewrite the practitioner's blocks from results/ wherever each lives."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
