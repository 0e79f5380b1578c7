"""Study part `ablations`: what the choice of human IK changes — the twin's whole-body solver vs
PyBullet's IK, on a coarser grid of the same boundary (PyBullet's IK runs ~380 locations/s, so
the paper's 3 mm grid would take hours). The objective (paper_postural / REBA / reba_ab / RULA)
and the temperature schedule (fixed / adaptive) are targets and agents of the `learning` part.

Writes results/ablations/: ik.csv (one row per solver and score), manifest.json; both solvers'
landscapes go to the landscape cache.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pandas as pd

from ...io.atomic import atomic_write_csv
from ...landscape.stats import statistics
from ...twin.evaluate import SOLVERS
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import grid_of, landscape


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.ablations

    def work(folder: Path) -> dict:
        rows = []
        for solver in SOLVERS:
            evaluator = dataclasses.replace(config.evaluator(), solver=solver)
            ik = landscape(engine, evaluator, grid_of(evaluator, part.ik_boundary,
                                                      part.ik_step))
            stats = statistics(ik)
            stats.insert(0, "solver", solver)
            stats["unbalanced_fraction"] = ((ik.arrays["flags"] & 4) > 0).mean()
            stats["grid"] = ik.grid.describe()
            rows.append(stats)
        atomic_write_csv(pd.concat(rows, ignore_index=True), folder / "ik.csv")
        return {"solvers": len(SOLVERS)}

    return run_part("ablations", results / "ablations", config.part_inputs("ablations"), work,
                    force=force, engine=engine)
