"""Study part `validation`: the twin beside published human data — its trunk, neck and arm
angles at the study's optimum against ISO 11226's acceptable static postures, the optimum's
height and reach against preferred working heights and lifting distances, and its knee, hip
and lumbar flexion at a box on the floor and at knee height against measured lifts; and the
legs and back of four workers (5th-percentile woman to 95th-percentile man) across the body
boundary's lowest row, at knee height.

Writes results/validation/validation.csv (one row per published condition: source, condition,
quantity, published mean, SD, the range checked, the box location, the twin's value, within),
results/validation/knee_height.csv (per worker and location: ankle, knee, hip and lumbar flexion
[deg] and the postural index), results/validation/handovers.csv (the twin where people received
an object in measured handovers: per handover, placement and quantity the receiver's angle and
the twin's, and the twin's scores there beside its own optimum; see
src/ergohandover/study/validation/handovers.py) and manifest.json. The conditions and their
citations are in src/ergohandover/study/validation/published.py.
"""

from __future__ import annotations

from pathlib import Path

from ...io.atomic import atomic_write_csv
from ...landscape.stats import optimum
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import default_landscape, grid_of, landscape
from .handovers import handover_table, receiver_twin, twin_description
from .published import knee_height_postures, validation_table

HANDOVER_STEP_M = 0.01
"""The receiver twin's landscape grid (the population's step): its optimum and how many of
its locations score better than where people took the object."""


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.validation

    def work(folder: Path) -> dict:
        best = optimum(default_landscape(config, engine), part.optimum_of)[1]
        table = validation_table(best, config.evaluator())
        atomic_write_csv(table, folder / "validation.csv")
        within = int(table["within"].sum())
        print(f"  {within} of {len(table)} conditions within the published range")
        knees = knee_height_postures(config.task())
        atomic_write_csv(knees, folder / "knee_height.csv")
        print(f"  knee height: knee {knees['knee_flexion'].min():.0f}-"
              f"{knees['knee_flexion'].max():.0f} deg, hip {knees['hip_flexion'].min():.0f}-"
              f"{knees['hip_flexion'].max():.0f} deg over {knees['worker'].nunique()} workers")
        twin = receiver_twin(config.task())
        handovers = handover_table(twin, landscape(engine, twin, grid_of(
            twin, config.landscape.boundary, HANDOVER_STEP_M)))
        atomic_write_csv(handovers, folder / "handovers.csv")
        angles = handovers[handovers["measured"].notna()]
        print(f"  measured handovers: {handovers['handover'].nunique()}, the twin's angles "
              f"{angles['difference'].abs().min():.0f}-{angles['difference'].abs().max():.0f} "
              "deg from the receivers'")
        return {"conditions": len(table), "within": within, "handover_twin":
                twin_description(twin), "handover_step_m": HANDOVER_STEP_M,
                "sources": int(table["source"].nunique()),
                "knee_height_locations": len(knees)}

    return run_part("validation", results / "validation", config.part_inputs("validation"),
                    work, force=force, engine=engine)
