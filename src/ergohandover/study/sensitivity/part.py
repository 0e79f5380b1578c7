"""Study part `sensitivity`: which modelling choices move the optimum? One landscape per
variant (every solver cost weight at x0.5 and x2, the joint preferences, gaze on/off, the joint
limits, the trunk-angle convention, box mass and handle span at -/+50%), swept side by side on
the engine on a coarser grid than the landscape part's (`step`, 1 cm by default: ~92,000 points
a variant), and the default on the same grid as their reference; the default on the study's
own grid heads the table.

Writes results/sensitivity/sensitivity.csv (one row per variant: minimum of the paper score,
REBA and RULA and the share of feasible points at it, the optimum, its shift from the default
optimum on the same grid [cm], whether the optimised location still beats the shortest-distance
one from all five of the paper's starts) and manifest.json.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

from ...io.atomic import atomic_write_csv
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import default_landscape, grid_of, landscapes
from .variants import Variant, sensitivity_row, variants


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.sensitivity

    def work(folder: Path) -> dict:
        base = config.evaluator()
        print("  the default's optimum and conclusion on the study's grid")
        rows = [sensitivity_row(Variant("default", "default (study grid)"),
                                default_landscape(config, engine), base, None)]
        chosen = variants(base)
        evaluators = [variant.evaluator(base) for variant in chosen]
        # Every variant on the grid of the default's boundary (a one-size grid, so that the
        # optima can be compared point for point).
        grid = grid_of(base, config.landscape.boundary, part.step)
        print(f"  {len(chosen)} variants on {grid.describe()}")
        found = landscapes(engine, evaluators, grid)
        reference = None
        # Each row scores the variant's optimum and the baselines' locations (about a second).
        for variant, evaluator, landscape in tqdm(zip(chosen, evaluators, found, strict=True),
                                                  total=len(chosen), unit="variant",
                                                  desc="variants' optima and conclusions"):
            row = sensitivity_row(variant, landscape, evaluator, reference)
            if reference is None:  # the first variant is the default on this grid
                reference = np.array([row["optimum_x"], row["optimum_y"], row["optimum_z"]])
                row["shift_cm"] = 0.0
            rows.append(row)
        table = pd.DataFrame(rows)
        atomic_write_csv(table, folder / "sensitivity.csv")
        return {"variants": len(table) - 2, "grid": rows[1]["grid"]}

    return run_part("sensitivity", results / "sensitivity", config.part_inputs("sensitivity"),
                    work, force=force, engine=engine)
