"""Study part `sensitivity`: which modelling choices move the optimum? One landscape per
variant (every solver cost weight at x0.5 and x2, the joint preferences, gaze on/off, the joint
limits, the trunk-angle convention, box mass and handle span at -/+50%), on a coarser grid than
the landscape part's (`step` in the config, 1 cm by default: ~92,000 points a variant), and the
default on the same grid as their reference; the default on the study's own grid heads the
table.

Usage: python experiments/study_sensitivity.py [--config experiments/configs/default.json]

Writes results/sensitivity/sensitivity.csv (one row per variant: minimum of the paper score,
REBA and RULA and the share of feasible points at it, the optimum, its shift from the default
optimum on the same grid [cm], whether the optimised location still beats the shortest-distance
one from all five of the paper's starts) and manifest.json.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import study_landscape

from ergohandover.io.atomic import atomic_write_csv
from ergohandover.study.parts import part_config, run_part, study_main
from ergohandover.study.sensitivity import Variant, sensitivity_row, variants
from ergohandover.twin.evaluate import Evaluator

ROOT = Path(__file__).resolve().parents[1]


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    study_landscape.run(config, results, workers)  # reused when finished
    part = part_config(config, "sensitivity")

    def work(folder: Path) -> dict:
        base = Evaluator(task=study_landscape.study_task(config))
        study_grid = study_landscape.default_landscape(config, workers)
        rows = [sensitivity_row(Variant("default", "default (study grid)"), study_grid, base,
                                None)]
        grid = {"boundary": config["landscape"]["boundary"], "step": part["step"]}
        reference = None
        for variant in variants(base):
            evaluator = variant.evaluator(base)
            print(f"  variant {variant.name}")
            landscape = study_landscape.landscape_of(evaluator, grid, workers)
            row = sensitivity_row(variant, landscape, evaluator, reference)
            if reference is None:  # the first variant is the default on this grid
                reference = np.array([row["optimum_x"], row["optimum_y"], row["optimum_z"]])
                row["shift_cm"] = 0.0
            rows.append(row)
        table = pd.DataFrame(rows)
        atomic_write_csv(table, folder / "sensitivity.csv")
        return {"variants": len(table) - 2, "grid": rows[1]["grid"]}

    run_part("sensitivity", results / "sensitivity", part, work, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
