"""Study part `shift`: joint fatigue over a working day of handovers.

First the fatigue model's constants, checked at a glance: each joint's time to failure under a
sustained load, from the three-compartment model's closed form with Frey-Law et al. 2012's
rates, beside the endurance power law fitted to 369 published endurance times (Frey-Law & Avin
2010) and its 95 % prediction band (src/ergohandover/workload/fatigue.py). Then the default
worker's shift at every location of the population's grid: each joint's moment as a share of
its strength (src/ergohandover/workload/strength.py), a shift of handovers at each rate and
hold, and where the location best for the shift lies beside the posture's optimum and the
robot's shortest-distance locations (the robustness part's headline locations: the baseline).

Writes results/shift/reference.csv (per joint and load of ``reference_loads``: the model's and
the power law's endurance times [s], their ratio, the band and whether the model lies in it,
and the joint's never-failing load), results/shift/curves.csv (the same every ``curve_step``
of load), results/shift/locations.csv (per rate and hold, each of :data:`LOCATIONS` and each
shortest-distance location with its shift columns), results/shift/trace.csv (per rate and hold,
each joint's capacity over the shift at the posture's optimum and each shortest-distance
location) and manifest.json.
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
from ...twin.evaluate import evaluate_arrays
from ...workload.fatigue import (
    JOINTS,
    POWER_LAW_BAND,
    capacity_over_shift,
    endurance_time,
    never_failing_load,
    power_law_endurance,
)
from ...workload.strength import JOINTS as LOADED_JOINTS
from ...workload.strength import shift_columns
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..robustness.recorded import headline_locations
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


def posture_of(arrays, index: np.ndarray, load_kg: float) -> Posture:
    """The Posture columns the landscape keeps (the trunk's, the neck's and both arms' angles)
    at rows ``index`` of ``arrays`` (a landscape's arrays or the twin's evaluated columns),
    every other angle upright, and the box's mass."""
    columns = {name: np.zeros(index.size) for name in REQUIRED_COLUMNS}
    for name in LANDSCAPE_ANGLES:
        if name in columns:
            columns[name] = np.asarray(arrays[name], dtype=float)[index]
    columns["right_knee_flexion"] = columns["left_knee_flexion"]
    columns["load_kg"] = np.full(index.size, load_kg)
    return Posture(columns)


LOCATIONS = ("posture-optimal", "best for the shift at the optimal score",
             "best for the shift alone")
"""The locations compared at each rate and hold: the paper score's optimum (the landscape's
rule); of the cells at that lowest score, the one whose joints keep the most capacity at the
shift's end (the lowest of the joints'; no joint failing; equal: the lower LiFFT dose); and of
every feasible cell, the same whatever its score (equal: the lower score). Beside them, the
robot's shortest-distance location from each start (the baseline: where a robot hands over
without the tool)."""
BASELINE = "shortest distance"
"""The headline locations read as the baseline (their names start with it)."""


def shift_table(found, evaluator, part, named: pd.DataFrame) -> tuple[pd.DataFrame,
                                                                     pd.DataFrame]:
    """Per rate and hold (those whose hold fits in the cycle): each of :data:`LOCATIONS` and
    each of the ``named`` baseline locations, with its shift columns
    (:func:`~...workload.strength.shift_columns`); and, at the posture's optimum and the
    baselines, each joint's capacity over the shift (:func:`trace_rows`: the figure's
    curves)."""
    cells = np.flatnonzero(found.feasible)
    load = evaluator.task.box_mass_kg
    posture = posture_of(found.arrays, cells, load)
    score = objective_values(found, "paper_postural")[cells]
    best = found.grid.nearest_cell(optimum(found, "paper_postural")[1])
    baseline = named[named["location"].str.startswith(BASELINE)].reset_index(drop=True)
    at = evaluate_arrays(baseline[["x", "y", "z"]].to_numpy(float), evaluator)
    taken = np.flatnonzero(at["feasible"])
    at_posture = posture_of(at, taken, load)
    rows, traces = [], []
    for plan in part.plans():
        columns = shift_columns(posture, evaluator.body, plan)
        capacity = np.nan_to_num(columns["shift_capacity_end"], nan=-1.0)
        at_best = np.where(score == score.min(), capacity, -2.0)
        chosen = (int(np.searchsorted(cells, best)),
                  int(np.lexsort((columns["lifft_dose"], -at_best))[0]),
                  int(np.lexsort((score, -capacity))[0]))
        said = {"rate_per_min": plan.rate_per_min, "hold_s": plan.hold_s, "hours": plan.hours,
                "handovers": plan.handovers}
        for kind, index in zip(LOCATIONS, chosen, strict=True):
            x, y, z = found.grid.point(int(cells[index]))
            rows.append({**said, "location": kind, "x": x, "y": y, "z": z,
                         "paper_postural": score[index],
                         **{k: float(v[index]) for k, v in columns.items()}})
        there = shift_columns(at_posture, evaluator.body, plan)
        row_of = {int(k): i for i, k in enumerate(taken)}  # a baseline the twin cannot take:
        for k, row in baseline.iterrows():  # its location and score, no shift columns
            rows.append({**said, "location": row["location"], "x": row["x"], "y": row["y"],
                         "z": row["z"], "paper_postural": float(at["paper_postural"][k]),
                         **({c: float(v[row_of[k]]) for c, v in there.items()}
                            if k in row_of else {})})
        shares = {"posture-optimal": {j: columns[f"{j}_load_share"][chosen[0]]
                                      for j in LOADED_JOINTS}}
        shares |= {baseline["location"][k]: {j: there[f"{j}_load_share"][i]
                                             for j in LOADED_JOINTS} for k, i in row_of.items()}
        traces += trace_rows(shares, plan, said)
    return pd.DataFrame(rows), pd.DataFrame(traces)


def trace_minutes(plan) -> np.ndarray:
    """When the figure's curves are read: every half minute for the first 15 minutes (the
    joints settle within minutes: the fatigue and recovery rates are about 1 % a second), then
    every 15 minutes, and the shift's end."""
    end = plan.hours * 60.0
    early = np.arange(0.0, min(15.0, end), 0.5)
    return np.unique(np.concatenate([early, np.arange(15.0, end, 15.0), [end]]))


def trace_rows(shares: dict[str, dict[str, float]], plan, said: dict) -> list[dict]:
    """Each location's joints' capacity before the handovers at :func:`trace_minutes` of the
    shift, and at its end (NaN once the joint has failed)."""
    minutes = trace_minutes(plan)
    handover = np.minimum((minutes * plan.rate_per_min).astype(int), plan.handovers)
    rows = []
    for location, joints in shares.items():
        for joint, share in joints.items():
            capacity = capacity_over_shift(share, joint, plan)[handover]
            rows += [{**said, "location": location, "joint": joint, "minute": m,
                      "capacity": c} for m, c in zip(minutes, capacity, strict=True)]
    return rows


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
        locations, traces = shift_table(found, evaluator, part, headline_locations(results))
        atomic_write_csv(locations, folder / "locations.csv")
        atomic_write_csv(traces, folder / "trace.csv")
        inside = int(reference["within_band"].sum())
        print(f"  the model's endurance times within the power laws' 95 % band at {inside} of "
              f"{len(reference)} joint-loads")
        return {"joints": len(JOINTS), "within_band": inside}

    return run_part("shift", results / "shift", config.part_inputs("shift"), work,
                    force=force, engine=engine)
