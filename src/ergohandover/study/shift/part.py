"""Study part `shift`: the fatigue model's constants checked at a glance. Each joint's time to
failure under a sustained load, from the three-compartment model's closed form with Frey-Law et
al. 2012's rates, beside the endurance power law fitted to 369 published endurance times
(Frey-Law & Avin 2010) and its 95 % prediction band (src/ergohandover/workload/fatigue.py).

Writes results/shift/reference.csv (per joint and load of ``reference_loads``: the model's and
the power law's endurance times [s], their ratio, the band and whether the model lies in it,
and the joint's never-failing load), results/shift/curves.csv (the same every ``curve_step``
of load) and manifest.json.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...io.atomic import atomic_write_csv
from ...workload.fatigue import (
    JOINTS,
    POWER_LAW_BAND,
    endurance_time,
    never_failing_load,
    power_law_endurance,
)
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part


def endurance_table(loads) -> pd.DataFrame:
    """Per joint and sustained load (share of strength): the model's closed-form endurance
    time, the power law's and its band [s], their ratio and whether the model is in the band,
    and the joint's never-failing load."""
    loads = np.asarray(loads, dtype=float)
    rows = []
    for joint in JOINTS:
        model, law = endurance_time(loads, joint), power_law_endurance(loads, joint)
        low, high = law * (1 - POWER_LAW_BAND), law * (1 + POWER_LAW_BAND)
        rows.append(pd.DataFrame({
            "joint": joint, "load": loads, "model_s": model, "power_law_s": law,
            "ratio": model / law, "band_low_s": low, "band_high_s": high,
            "within_band": (model >= low) & (model <= high),
            "never_fails_below": never_failing_load(joint)}))
    return pd.concat(rows, ignore_index=True)


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.shift

    def work(folder: Path) -> dict:
        reference = endurance_table(part.reference_loads)
        atomic_write_csv(reference, folder / "reference.csv")
        steps = np.arange(1, round(1 / part.curve_step) + 1) * part.curve_step
        atomic_write_csv(endurance_table(steps), folder / "curves.csv")
        inside = int(reference["within_band"].sum())
        print(f"  the model's endurance times within the power laws' 95 % band at {inside} of "
              f"{len(reference)} joint-loads")
        return {"joints": len(JOINTS), "within_band": inside}

    return run_part("shift", results / "shift", config.part_inputs("shift"), work,
                    force=force, engine=engine)
