"""Compare two results folders (e.g. the committed results/ and a rerun): every score,
location, count and step must be equal; wall-time columns may differ, and their spread is
printed. Learning runs under a wall-clock cap are left out (how far a run gets in 2 s depends on
the machine's load); every step-budgeted run must repeat exactly.

Usage: python experiments/analysis/compare_runs.py RESULTS_A RESULTS_B [PART ...]
(PART: compare only these parts' tables, e.g. population after a run with --engine ray.)
Exit code 1 if anything but a wall time differs.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd

TABLES = ("landscape/stats.csv", "landscape/distribution.csv", "landscape/variants.csv",
          "landscape/gaze_effect.csv", "learning/targets.csv", "learning/runs.csv",
          "learning/summary.csv", "learning/comparisons.csv", "learning/curves.csv",
          "learning/found.csv", "baselines/baselines.csv", "baselines/other_starts.csv",
          "baselines/reachability.csv", "baselines/reachability_summary.csv", "ablations/ik.csv",
          "participants/participants.csv",
          *(f"population/{n}.csv" for n in ("workers", "penalties", "one_size", "groups",
                                            "height_fit", "working_heights")),
          "sensitivity/sensitivity.csv", "validation/validation.csv",
          "validation/knee_height.csv")
TIME_COLUMNS = {"elapsed_s", "steps_per_s", "planning_s", "median_steps_per_s"}


def read(folder: Path, name: str) -> pd.DataFrame:
    table = pd.read_csv(folder / name)
    if name in ("learning/runs.csv", "learning/summary.csv"):
        # wall-clock-capped runs depend on the machine's load
        table = table[table["steps"].notna()].reset_index(drop=True)
    if name in ("learning/found.csv", "learning/comparisons.csv"):
        # the study names wall-clock budgets wall-<cap>s
        table = table[~table["budget"].str.startswith("wall-")].reset_index(drop=True)
    return table


def compare(a: Path, b: Path, parts: list[str] | None = None) -> bool:
    same = True
    for name in TABLES:
        if parts and name.split("/")[0] not in parts:
            continue
        missing = [str(folder) for folder in (a, b) if not (folder / name).exists()]
        if missing:
            print(f"{name}: MISSING in {' and '.join(missing)}")
            same = False
            continue
        x, y = read(a, name), read(b, name)
        exact = [c for c in x.columns if c not in TIME_COLUMNS]
        if not x[exact].equals(y[exact]):
            diff = [c for c in exact if not x[c].equals(y[c])]
            print(f"{name}: DIFFERS in {diff}")
            same = False
        else:
            print(f"{name}: identical ({len(x)} rows" + (
                f"; wall-time columns {sorted(TIME_COLUMNS & set(x.columns))} differ)"
                if TIME_COLUMNS & set(x.columns) else ")"))
        for column in sorted(TIME_COLUMNS & set(x.columns)):
            big = (x[column] > 0.05) & (y[column] > 0.05)  # sub-50 ms times are noise
            if big.any():
                ratio = (y.loc[big, column] / x.loc[big, column]).to_numpy()
                print(f"   {column}: rerun/original over {big.sum()} runs above 50 ms: median "
                      f"{np.median(ratio):.2f}, range {ratio.min():.2f}-{ratio.max():.2f}")
    return same


if __name__ == "__main__":
    if len(sys.argv) < 3 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        sys.exit(0 if len(sys.argv) > 1 and sys.argv[1] in ("-h", "--help") else 2)
    sys.exit(0 if compare(Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3:]) else 1)
