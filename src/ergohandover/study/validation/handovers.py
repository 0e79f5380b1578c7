"""The twin beside people receiving an object in measured human-human handovers.

The measured side is ``handover_reference.json``: figures derived from the Handovers@RPL
motion-capture data set (Khanna, Bjorkman & Smith 2023; MIT licence) by
``experiments/tools/derive_handover_reference.py``, which a user can rerun on their own copy of
the data. Per handover, at the moment the object changes hands: where the object and the
receiver's wrist are relative to the receiver's pelvis, and the receiver's trunk inclination,
upper-arm elevation and elbow flexion.

The twin is put where the receiver took the object, in its own frame (the pelvis taken as
standing above the middle of the feet, which the data cannot check: the legs are not tracked),
and solved there three ways:

* ``object``: the study's box, its centre at the object's centre, laterally where the object
  was;
* ``hand``: the study's box, its centre at the receiving wrist's height and reach, on the
  midline (where the twin's hands would be, holding a box in front of it);
* ``baton``: as the receiver did, a baton taken in the receiving hand alone, its grip at the
  object's centre (scores not compared with the box's landscape: another task).

The twin is sized like the data set's participants: a man of their mean stature (the
recordings do not say who received), the rest of the body from the survey's body model. Its
scores there are set beside the best of its own landscape: does the receiver take the object
where the twin's landscape is good?
"""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

from ...landscape import Landscape
from ...landscape.stats import optimum
from ...twin.anthropometry import BodySpec
from ...twin.evaluate import Evaluator, evaluate
from ...twin.task import TaskSpec
from .published import MEASURES, elevation

REFERENCE = Path(__file__).with_name("handover_reference.json")
SCORES = ("paper_postural", "reba", "rula")


def reference() -> dict:
    """The measured handovers and their source."""
    return json.loads(REFERENCE.read_text())


def receiver_twin(task, data: dict | None = None) -> Evaluator:
    """The twin sized like the data set's participants: a man of their mean stature."""
    data = data or reference()
    stature = data["source"]["metadata"]["stature_cm"]["mean"] / 100.0
    return Evaluator(BodySpec.from_measurements({"stature_m": round(stature, 3)}), task)


def placements(handover: dict) -> dict[str, np.ndarray | None]:
    """Each placement's box centre in the worker frame (x right, y up, z forward) [m], or
    None where the recording lacks the landmark."""
    obj = handover["positions"]["baton"]
    side = "R" if handover["hand"] == "right" else "L"
    wrist = handover["positions"][f"wrist_{side}"]
    hand = None if wrist["height_m"] is None else \
        np.array([0.0, wrist["height_m"], wrist["forward_m"]])
    at_object = np.array([-obj["left_m"], obj["height_m"], obj["forward_m"]])
    return {"object": at_object, "hand": hand, "baton": at_object}


def twin_angles(row: pd.Series, side: str) -> dict[str, float]:
    """The twin's quantities named as the data's: trunk inclination, the receiving side's
    upper-arm elevation from the trunk and elbow flexion [deg]."""
    return {"trunk_inclination_deg": float(MEASURES["trunk_inclination"](row, None)),
            "upper_arm_elevation_trunk_deg": elevation(row, side),
            "elbow_flexion_deg": float(row[f"{side}_elbow_flexion"])}


def measured_angles(handover: dict) -> dict[str, float | None]:
    receiving = handover["angles"]["receiving"]
    return {"trunk_inclination_deg": handover["angles"]["trunk"]["inclination_deg"],
            "upper_arm_elevation_trunk_deg": receiving["upper_arm_elevation_trunk_deg"],
            "elbow_flexion_deg": receiving["elbow_flexion_deg"]}


def handover_table(evaluator: Evaluator, landscape: Landscape,
                   data: dict | None = None) -> pd.DataFrame:
    """One row per handover, placement and quantity: the measured value, the twin's and their
    difference; then, per handover and placement, the twin's scores there beside its own
    optimum and the share of its feasible locations that score better."""
    data = data or reference()
    # The landscape's optimum and feasible scores, once per score (every placement needs them).
    own = {}
    for score in SCORES:
        cells, _ = optimum(landscape, score)
        values = landscape.arrays[score]
        own[score] = (int(values[cells[0]]), values[values >= 0])
    rows = []
    for handover in data["handovers"]:
        side = handover["hand"]
        one_hand = replace(evaluator, task=TaskSpec.holding(
            "baton", hands=side, gaze=evaluator.task.gaze))
        for placement, point in placements(handover).items():
            if point is None:
                continue
            base = {"handover": handover["id"], "hand": side, "placement": placement,
                    **dict(zip("xyz", np.round(point, 3).tolist(), strict=True))}
            twin_of = one_hand if placement == "baton" else evaluator
            row = evaluate(point[None], twin_of).iloc[0]
            feasible = bool(row["feasible"])
            twin = twin_angles(row, side) if feasible else {}
            for quantity, measured in measured_angles(handover).items():
                if measured is None:
                    continue
                value = twin.get(quantity, math.nan)
                rows.append({**base, "quantity": quantity, "measured": measured,
                             "twin": round(value, 1), "difference": round(value - measured, 1),
                             "feasible": int(feasible)})
            for score, (best, feasible_values) in own.items():
                here = int(row[score]) if feasible else math.nan
                if placement == "baton":  # the box's landscape is another task's
                    best, better = math.nan, math.nan
                else:
                    better = float(np.mean(feasible_values < here)) if feasible else math.nan
                rows.append({**base, "quantity": f"{score}_score", "measured": math.nan,
                             "twin": here, "difference": here - best if feasible else math.nan,
                             "feasible": int(feasible), "twin_optimum": best,
                             "share_better": round(better, 4)})
    return pd.DataFrame(rows)


def twin_description(evaluator: Evaluator) -> dict:
    """The receiver twin's body, for the manifest."""
    body = evaluator.body
    return {"sex": body.sex, "stature_m": body.stature_m, "mass_kg": body.mass_kg,
            "proportions": body.proportions, "elbow_height_m": round(body.elbow_height_m, 4),
            "shoulder_height_m": round(body.shoulder_height_m, 4)}
