"""Study part `shift`: joint fatigue over a working day of handovers.

First the fatigue model's constants, checked at a glance: each joint's time to failure under a
sustained load, from the three-compartment model's closed form with Frey-Law et al. 2012's
rates, beside the endurance power law fitted to 369 published endurance times (Frey-Law & Avin
2010) and its 95 % prediction band (src/ergohandover/workload/fatigue.py). Then the default
worker's shift at every location of the population's grid: each joint's moment as a share of
its strength (src/ergohandover/workload/strength.py), a shift of handovers at each rate and
hold, and where the location best for the shift lies beside the posture's optimum.

Writes results/shift/reference.csv (per joint and load of ``reference_loads``: the model's and
the power law's endurance times [s], their ratio, the band and whether the model lies in it,
and the joint's never-failing load), results/shift/curves.csv (the same every ``curve_step``
of load), results/shift/locations.csv (per rate and hold, each of :data:`LOCATIONS` with its
shift columns) and manifest.json.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...envs.scores import objective_values
from ...ergonomics import Posture
from ...ergonomics.posture import REQUIRED_COLUMNS
from ...io.atomic import atomic_write_csv
from ...landscape.stats import optimum
from ...landscape.sweep import ANGLES as LANDSCAPE_ANGLES
from ...workload.fatigue import (
    JOINTS,
    POWER_LAW_BAND,
    Shift,
    endurance_time,
    never_failing_load,
    power_law_endurance,
)
from ...workload.strength import shift_columns
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import grid_of, landscape


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


def posture_of(found, load_kg: float) -> Posture:
    """The Posture columns a landscape holds at its feasible cells (the trunk's, the neck's and
    both arms' angles), every other angle upright, and the box's mass."""
    cells = np.flatnonzero(found.feasible)
    columns = {name: np.zeros(cells.size) for name in REQUIRED_COLUMNS}
    for name in LANDSCAPE_ANGLES:
        if name in columns:
            columns[name] = found.arrays[name][cells].astype(float)
    columns["right_knee_flexion"] = columns["left_knee_flexion"]
    columns["load_kg"] = np.full(cells.size, load_kg)
    return Posture(columns)


LOCATIONS = ("posture-optimal", "best for the shift at the optimal score",
             "best for the shift alone")
"""The locations compared at each rate and hold: the paper score's optimum (the landscape's
rule); of the cells at that lowest score, the one whose joints keep the most capacity at the
shift's end (the lowest of the joints'; no joint failing; equal: the lower LiFFT dose); and of
every feasible cell, the same whatever its score (equal: the lower score)."""


def shift_table(found, evaluator, part) -> pd.DataFrame:
    """Per rate and hold (those whose hold fits in the cycle): each of :data:`LOCATIONS`, with
    its shift columns (:func:`~...workload.strength.shift_columns`)."""
    cells = np.flatnonzero(found.feasible)
    posture = posture_of(found, evaluator.task.box_mass_kg)
    score = objective_values(found, "paper_postural")[cells]
    best = found.grid.nearest_cell(optimum(found, "paper_postural")[1])
    rows = []
    for rate in part.rates_per_min:
        for hold in part.holds_s:
            if hold >= 60.0 / rate:
                continue
            plan = Shift(rate, hold, part.hours)
            columns = shift_columns(posture, evaluator.body, plan)
            capacity = np.nan_to_num(columns["shift_capacity_end"], nan=-1.0)
            at_best = np.where(score == score.min(), capacity, -2.0)
            chosen = (int(np.searchsorted(cells, best)),
                      int(np.lexsort((columns["lifft_dose"], -at_best))[0]),
                      int(np.lexsort((score, -capacity))[0]))
            for kind, index in zip(LOCATIONS, chosen, strict=True):
                x, y, z = found.grid.point(int(cells[index]))
                rows.append({"rate_per_min": rate, "hold_s": hold, "hours": part.hours,
                             "handovers": plan.handovers, "location": kind, "x": x, "y": y,
                             "z": z, "paper_postural": score[index],
                             **{k: float(v[index]) for k, v in columns.items()}})
    return pd.DataFrame(rows)


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.shift

    def work(folder: Path) -> dict:
        reference = endurance_table(part.reference_loads)
        atomic_write_csv(reference, folder / "reference.csv")
        steps = np.arange(1, round(1 / part.curve_step) + 1) * part.curve_step
        atomic_write_csv(endurance_table(steps), folder / "curves.csv")
        evaluator = config.evaluator(config.population.reference)
        grid = grid_of(evaluator, config.population.boundary, config.population.step)
        found = landscape(engine, evaluator, grid)
        locations = shift_table(found, evaluator, part)
        atomic_write_csv(locations, folder / "locations.csv")
        inside = int(reference["within_band"].sum())
        print(f"  the model's endurance times within the power laws' 95 % band at {inside} of "
              f"{len(reference)} joint-loads")
        return {"joints": len(JOINTS), "within_band": inside}

    return run_part("shift", results / "shift", config.part_inputs("shift"), work,
                    force=force, engine=engine)
