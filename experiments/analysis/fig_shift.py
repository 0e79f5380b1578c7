"""Figure and report table: the fatigue model's constants at a glance. Per joint, the time a
sustained load is held before the joint fails, from the three-compartment model's closed form
(Frey-Law et al. 2012's rates) as a line, beside the endurance power law fitted to published
endurance times (Frey-Law & Avin 2010) dashed, in its 95 % prediction band. Reads
results/shift/curves.csv and results/shift/reference.csv; rewrites the report's
``shift-reference`` block."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from common import RESULTS, caption, read, save
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
    curves = read("shift/curves.csv")
    joints = list(dict.fromkeys(curves["joint"]))
    fig, axes = plt.subplots(2, (len(joints) + 1) // 2, figsize=(12, 6), sharex=True,
                             sharey=True, squeeze=False)
    for ax, joint in zip(axes.ravel(), joints, strict=False):
        table = curves[(curves["joint"] == joint) & (curves["load"] >= 0.1)]
        load = 100 * table["load"]
        ax.fill_between(load, table["band_low_s"], table["band_high_s"], color="tab:orange",
                        alpha=0.2, label="power law's 95 % band")
        ax.plot(load, table["power_law_s"], "--", color="tab:orange",
                label="power law (published endurance times)")
        ax.plot(load, table["model_s"], color="tab:blue", label="three-compartment model")
        never = 100 * table["never_fails_below"].iloc[0]
        ax.axvline(never, color="0.5", lw=0.8)
        ax.set_title(f"{joint} (never fails below {never:.1f} %)", fontsize=9)
        ax.set_yscale("log")
        ax.grid(True, which="major", alpha=0.3)
    for ax in axes.ravel()[len(joints):]:
        ax.axis("off")
    for ax in axes[-1]:
        ax.set_xlabel("sustained load [% of strength]")
    for ax in axes[:, 0]:
        ax.set_ylabel("time to failure [s]")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower right", fontsize=8, frameon=False,
               bbox_to_anchor=(0.98, 0.08))
    fig.suptitle(f"Each joint's endurance under a sustained load: the fatigue model beside the "
                 f"published power law (N = {len(joints)} joints; the power laws fitted to 369 "
                 "endurance times from 194 studies)", fontsize=10)
    caption(fig, "Model: Frey-Law, Looft & Heitsman 2012's rates (J Biomech 45:1803), closed "
                 "form. Power law: Frey-Law & Avin 2010 (Ergonomics 53:109), fitted to 10–100 % "
                 "of strength; band ±47 %, the widest of its joints' 95 % prediction bands. "
                 "Grey line: the load at and below which the model never fails.")
    save(fig, "shift_reference.png")
    rewrite(blocks(RESULTS))


if __name__ == "__main__":
    main()
