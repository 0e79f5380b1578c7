"""Study part `validation`: the twin beside published human data — its trunk, neck and arm
angles at the study's optimum against ISO 11226's acceptable static postures, the optimum's
height and reach against preferred working heights and lifting distances, and its knee, hip
and lumbar flexion at a box on the floor and at knee height against measured lifts; and the
legs and back of four workers (5th-percentile woman to 95th-percentile man) across the body
boundary's lowest row, at knee height.

Usage: python experiments/study_validation.py [--config experiments/configs/default.json]

Writes results/validation/validation.csv (one row per published condition: source, condition,
quantity, published mean, SD, the range checked, the box location, the twin's value, within),
results/validation/knee_height.csv (per worker and location: ankle, knee, hip and lumbar flexion
[deg] and the postural index) and manifest.json. The conditions and their citations are in
src/ergohandover/study/validation.py.
"""

from __future__ import annotations

from pathlib import Path

import study_landscape

from ergohandover.io.atomic import atomic_write_csv
from ergohandover.landscape.stats import optimum
from ergohandover.study.parts import part_config, run_part, study_main
from ergohandover.study.validation import knee_height_postures, validation_table
from ergohandover.twin.evaluate import Evaluator

ROOT = Path(__file__).resolve().parents[1]


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    study_landscape.run(config, results, workers)  # reused when finished
    part = part_config(config, "validation")

    def work(folder: Path) -> dict:
        landscape = study_landscape.default_landscape(config, workers)
        best = optimum(landscape, part["optimum_of"])[1]
        table = validation_table(best, Evaluator(task=study_landscape.study_task(config)))
        atomic_write_csv(table, folder / "validation.csv")
        within = int(table["within"].sum())
        print(f"  {within} of {len(table)} conditions within the published range")
        knees = knee_height_postures(study_landscape.study_task(config))
        atomic_write_csv(knees, folder / "knee_height.csv")
        print(f"  knee height: knee {knees['knee_flexion'].min():.0f}-"
              f"{knees['knee_flexion'].max():.0f} deg, hip {knees['hip_flexion'].min():.0f}-"
              f"{knees['hip_flexion'].max():.0f} deg over {knees['worker'].nunique()} workers")
        return {"conditions": len(table), "within": within,
                "sources": int(table["source"].nunique()),
                "knee_height_locations": len(knees)}

    run_part("validation", results / "validation", part, work, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
