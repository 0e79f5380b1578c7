"""The validation's measured-handover table in Markdown, from results/validation/ only: the
twin beside people receiving an object in recorded handovers. make_tables.py puts it into
results/tables.md; docs/report.md carries it and a test keeps the two equal;
``python validation_tables.py`` rewrites the report's block."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
from readme_blocks import rewrite

QUANTITIES = {"trunk_inclination_deg": "trunk inclination",
              "upper_arm_elevation_trunk_deg": "upper-arm elevation from the trunk",
              "elbow_flexion_deg": "elbow flexion"}
PLACEMENTS = {"object": "box where the object was", "hand": "box at the receiving hand",
              "baton": "baton in the receiving hand where the object was"}
SCORES = {"paper_postural_score": "postural score", "reba_score": "REBA", "rula_score": "RULA"}


def handover_table(table: pd.DataFrame) -> list[str]:
    """Per handover and placement: the receiver's angles beside the twin's, and the twin's
    scores there beside its own optimum."""
    lines = ["| handover | placement (x, y, z) [m] | " + " | ".join(
        f"{name}: receiver / twin [deg]" for name in QUANTITIES.values()) + " | " + " | ".join(
        f"{name}: twin there / its optimum (share of its locations better)"
        for name in SCORES.values()) + " |", "|---|---|" + "---|" * (len(QUANTITIES) + 3)]
    for (handover, placement), rows in table.groupby(["handover", "placement"], sort=False):
        rows = rows.set_index("quantity")
        first = rows.iloc[0]
        cells = []
        for quantity in QUANTITIES:
            if quantity in rows.index:
                r = rows.loc[quantity]
                cells.append(f"{r.measured:.1f} / {r.twin:.1f}")
            else:
                cells.append("not recorded")
        for score in SCORES:
            r = rows.loc[score]
            if not r.feasible:
                cells.append("infeasible")
            elif r.twin_optimum != r.twin_optimum:  # another task: no optimum to compare
                cells.append(f"{r.twin:.0f} / – (another task)")
            else:
                cells.append(f"{r.twin:.0f} / {r.twin_optimum:.0f} ({r.share_better:.0%})")
        name = handover.split("/")[0]
        lines.append(f"| {name} | {PLACEMENTS[placement]} ({first.x:.3f}, {first.y:.3f}, "
                     f"{first.z:.3f}) | " + " | ".join(cells) + " |")
    return lines


def blocks(results: Path) -> dict[str, str]:
    """Each generated block's text, from ``results``/validation/ only."""
    table = pd.read_csv(results / "validation" / "handovers.csv")
    return {"validation-handovers": "\n" + "\n".join(handover_table(table)) + "\n"}


def main() -> None:
    """Rewrite the validation block of docs/report.md from results/ (run after the study)."""
    from common import RESULTS

    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
