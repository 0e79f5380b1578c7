"""Study part `ablations`: what the choice of human IK changes — our whole-body solver vs
PyBullet's IK, on a coarser grid of the same boundary (PyBullet's IK runs ~380 locations/s, so
the paper's 3 mm grid would take hours). The objective (paper_postural / REBA / reba_ab / RULA)
and the temperature schedule (fixed / adaptive) are targets and agents of the `learning` part.

Usage: python experiments/study_ablations.py [--config ...]

Writes results/ablations/: ik.csv (one row per solver and score), manifest.json; both solvers'
landscapes go to the landscape cache.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import study_landscape

from ergohandover.io.atomic import atomic_write_csv
from ergohandover.landscape.stats import statistics
from ergohandover.study.parts import part_config, run_part, study_main
from ergohandover.twin.anthropometry import BodySpec

ROOT = Path(__file__).resolve().parents[1]


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    study_landscape.run(config, results, workers)  # reused when finished
    part = part_config(config, "ablations")

    def work(folder: Path) -> dict:
        ik_grid = {"boundary": part["ik_boundary"], "step": part["ik_step"]}
        rows = []
        for solver in ("numpy", "pybullet"):
            ik = study_landscape.landscape_for(BodySpec(), ik_grid, workers, solver,
                                              study_landscape.study_task(config))
            stats = statistics(ik)
            stats.insert(0, "solver", solver)
            stats["unbalanced_fraction"] = ((ik.arrays["flags"] & 4) > 0).mean()
            stats["grid"] = ik.grid.describe()
            rows.append(stats)
        atomic_write_csv(pd.concat(rows, ignore_index=True), folder / "ik.csv")
        return {"solvers": 2}

    run_part("ablations", results / "ablations", part, work, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
