"""Study part `ablations`: what each choice changes.

- objective: paper_postural / reba / reba_ab / rula — each landscape minimum and how fast
  Q-learning reaches it;
- temperature: the published code's fixed 0.7 vs the paper's adaptive schedule;
- human IK: our whole-body solver vs PyBullet's IK, on a coarser grid of the same boundary
  (PyBullet's IK runs ~380 locations/s, so the paper's 3 mm grid would take hours).

Usage: python experiments/study_ablations.py [--config ...]

Writes results/ablations/: objectives.csv, temperature.csv (one row per run), ik.csv (one row
per solver and score), manifest.json; both solvers' landscapes go to the landscape cache.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import study_landscape
from study_learning import run_jobs, write_runs

from ergohandover.io.atomic import atomic_write_csv
from ergohandover.landscape.cache import landscape_path
from ergohandover.landscape.stats import statistics
from ergohandover.learning.search import exhaustive
from ergohandover.study.parts import part_config, run_part, study_main
from ergohandover.twin.anthropometry import BodySpec

ROOT = Path(__file__).resolve().parents[1]


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    study_landscape.run(config, results, workers)  # reused when finished
    part = part_config(config, "ablations")

    def work(folder: Path) -> dict:
        landscape = study_landscape.default_landscape(config, workers)
        landscape_file = landscape_path(landscape.key)
        truths = {o: exhaustive(landscape, o) for o in part["objectives"]}
        base = {"cap_s": part["cap_s"], "landscape": str(landscape_file), "agent": "qlearning"}
        jobs = [{**base, "objective": o, "temperature": t, "seed": seed,
                 "stop_score": truths[o].score}
                for o in part["objectives"] for t in part["temperatures"]
                for seed in range(part["seeds"])]
        runs = write_runs(run_jobs(jobs, workers, "ablations"), folder)
        atomic_write_csv(runs[runs["temperature"] == "fixed"], folder / "objectives.csv")
        atomic_write_csv(runs[runs["objective"] == "paper_postural"], folder / "temperature.csv")
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
        return {"runs": len(runs)}

    run_part("ablations", results / "ablations", part, work,
             seeds={"runs": part["seeds"]}, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
