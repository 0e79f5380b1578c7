"""Does the twin stand as people do? Its angles and chosen locations beside published human data.

Each :class:`Condition` is one published number (a mean with its SD, a range of reported means,
or a standard's acceptable zone) with its full citation, the box location it applies to and the
twin's quantity compared with it. The twin is the default worker (ANSUR II 50th-percentile man)
holding the default box; ``within`` says whether its value lies in the published range (mean ±
1 SD where an SD is published).

Locations: ``optimum`` is the study's paper-score optimum (where the robot would hand the box
over); ``knee`` and ``floor`` hold the box at the worker's knee height and on the floor, its
near edge 23.6 cm in front of the ankles (the mean gap people leave, Potvin & Bent 1997).

Every number below was read in the cited text (or, where marked "as quoted in" or "as
implemented in", in the document named); none is estimated.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import pandas as pd

from ...twin.anthropometry import BodySpec
from ...twin.evaluate import Evaluator, evaluate
from ...twin.task import Boundary

ISO_11226 = ("ISO 11226:2000, Ergonomics - Evaluation of static working postures (with EN "
             "1005-4:2005), as implemented in hfelabs-boop/ErgoCapture "
             "src/lib/ergo/staticPosture.ts")
MAGNUSSON = ("Magnusson M, Ortengren R (1987). Investigation of optimal table height and surface "
             "angle in meatcutting. Applied Ergonomics 18(2):146-152")
GRANDJEAN = ("Grandjean E (1979). Fitting the Task to the Man. Taylor & Francis; as quoted in "
             + MAGNUSSON + ", p. 148")
PHEASANT = ("Pheasant S, Haslegrave CM (2006). Bodyspace: Anthropometry, Ergonomics and the Design "
            "of Work, 3rd ed. Taylor & Francis; as quoted by msdprevention.com, 'Standing "
            "workstation height for manual tasks'")
POTVIN = ("Potvin JR, Bent LR (1997). NIOSH equation horizontal distances associated with the "
          "Liberty Mutual (Snook) lifting table box widths. Ergonomics 40(6):650-655. "
          "doi:10.1080/001401397187946")
PLAMONDON = ("Plamondon A, Denis D, Delisle A, Lariviere C, Salazar E, IRSST MMH research group "
             "(2010). Biomechanical differences between expert and novice workers in a manual "
             "material handling task. Ergonomics 53(10):1239-1253")
SCHELLENBERG = ("Schellenberg F, Lindorfer J, List R, Taylor WR, Lorenzetti S (2013). Kinetic "
                "and kinematic differences between deadlifts and goodmornings. BMC Sports Science, "
                "Medicine and Rehabilitation 5:27. doi:10.1186/2052-1847-5-27")
GAP_M = 0.236  # mean gap between the ankles and the near edge of a lifted box (Potvin & Bent)


class Condition(NamedTuple):
    """One published number and the twin's quantity it is compared with.

    ``published``: the mean (or the zone's limit); ``published_sd``: its SD (NaN if none);
    ``low``, ``high``: the range the twin must fall in; ``basis``: what that range is.
    """

    source: str
    condition: str
    quantity: str
    published: float
    published_sd: float
    low: float
    high: float
    basis: str
    location: str  # optimum | knee | floor
    measure: str  # a key of MEASURES


def _sd_range(mean: float, sd: float) -> tuple[float, float, float, float]:
    return mean, sd, mean - sd, mean + sd


NAN = math.nan
CONDITIONS = (
    Condition(ISO_11226, "static posture, trunk without support", "trunk inclination from "
              "vertical [deg]", 20.0, NAN, 0.0, 20.0, "acceptable zone (0-20 deg)",
              "optimum", "trunk_inclination"),
    Condition(ISO_11226, "static posture, head without support", "neck flexion [deg]", 25.0,
              NAN, 0.0, 25.0, "acceptable zone (0-25 deg)", "optimum", "neck_flexion"),
    Condition(ISO_11226, "static posture, arm without support", "upper-arm elevation, worse "
              "arm [deg]", 20.0, NAN, 0.0, 20.0, "acceptable zone (0-20 deg)", "optimum",
              "upper_arm_elevation"),
    Condition(ISO_11226, "static posture held", "trunk side bend or twist, larger [deg]", 10.0,
              NAN, 0.0, 10.0, "acceptable (more than 10 deg held: not acceptable)", "optimum",
              "trunk_side_bend_or_twist"),
    Condition(MAGNUSSON, "standing manual work (20 butchers), most comfortable table height",
              "hand height below elbow height [cm]", 19.5, NAN, 17.0, 22.0,
              "published range 17-22 cm", "optimum", "below_elbow_cm"),
    Condition(GRANDJEAN, "standing light work", "hand height below elbow height [cm]", 12.5, NAN,
              10.0, 15.0, "recommended range 10-15 cm", "optimum", "below_elbow_cm"),
    Condition(PHEASANT, "standing light work (assembly, small tools)", "hand height below elbow "
              "height [cm]", 7.5, NAN, 5.0, 10.0, "recommended range 5-10 cm", "optimum",
              "below_elbow_cm"),
    Condition(POTVIN, "box lifts from floor, knuckle and shoulder height (24 adults, boxes 34-75 "
              "cm wide)", "horizontal distance hands to mid-ankles [cm]", 45.0, NAN, 44.0, 57.0,
              "range of the reported pooled means (45 at knuckle height)", "optimum",
              "hands_to_ankles_cm"),
    Condition(PLAMONDON, "boxes from a conveyor to a hand trolley, 15 expert handlers",
              "knee flexion [deg]", *_sd_range(72.0, 30.0), "mean +/- 1 SD (printed as approx.)",
              "knee", "knee_flexion"),
    Condition(PLAMONDON, "boxes from a conveyor to a hand trolley, 15 expert handlers",
              "lumbar flexion [deg]", *_sd_range(54.0, 11.0), "mean +/- 1 SD", "knee",
              "lumbar_flexion"),
    Condition(PLAMONDON, "boxes from a conveyor to a hand trolley, 15 novice handlers",
              "knee flexion [deg]", *_sd_range(53.0, 33.0), "mean +/- 1 SD (printed as approx.)",
              "knee", "knee_flexion"),
    Condition(PLAMONDON, "boxes from a conveyor to a hand trolley, 15 novice handlers",
              "lumbar flexion [deg]", *_sd_range(66.0, 15.0), "mean +/- 1 SD", "knee",
              "lumbar_flexion"),
    Condition(SCHELLENBERG, "deadlift from the floor, 25% body weight (13 subjects; a barbell, "
              "not a box)", "maximal knee flexion [deg]", *_sd_range(107.8, 22.4),
              "mean +/- 1 SD", "floor", "knee_flexion"),
    Condition(SCHELLENBERG, "deadlift from the floor, 25% body weight (13 subjects; a barbell, "
              "not a box)", "maximal hip flexion [deg]", *_sd_range(103.2, 4.8), "mean +/- 1 SD",
              "floor", "hip_flexion"),
)


def locations(evaluator: Evaluator, optimum: np.ndarray) -> dict[str, np.ndarray]:
    """The box locations of the conditions for the evaluator's worker, worker frame [m]."""
    body, task = evaluator.body, evaluator.task
    near = GAP_M + task.box_depth / 2.0  # box centre in front of the ankles
    return {"optimum": np.asarray(optimum, dtype=float),
            "knee": np.array([0.0, body.segments().knee_height, near]),
            "floor": np.array([0.0, task.box_height / 2.0, near])}


def elevation(row: pd.Series, side: str) -> float:
    """Upper-arm elevation from the trunk's downward axis [deg]: flexion is the arm's angle in
    the sagittal plane and abduction its angle out of it, so cos(elevation) is their product."""
    flexion = math.radians(row[f"{side}_upper_arm_flexion"])
    abduction = math.radians(row[f"{side}_upper_arm_abduction"])
    return math.degrees(math.acos(math.cos(flexion) * math.cos(abduction)))


MEASURES = {
    "trunk_inclination": lambda row, body: row["trunk_flexion"],
    "neck_flexion": lambda row, body: row["neck_flexion"],
    "upper_arm_elevation": lambda row, body: max(elevation(row, s) for s in ("left", "right")),
    "trunk_side_bend_or_twist": lambda row, body: max(abs(row["trunk_side_bend"]),
                                                      abs(row["trunk_twist"])),
    "below_elbow_cm": lambda row, body: (body.elbow_height_m - row["y"]) * 100.0,
    "hands_to_ankles_cm": lambda row, body: row["z"] * 100.0,
    "knee_flexion": lambda row, body: row["left_knee_flexion"],
    "lumbar_flexion": lambda row, body: math.degrees(row["q_lumbar_flexion"]),
    "hip_flexion": lambda row, body: math.degrees(row["q_hip_flexion"]),
}


def validation_table(optimum: np.ndarray, evaluator: Evaluator | None = None) -> pd.DataFrame:
    """One row per condition: the published numbers, the twin's value and whether it is within.

    Args:
        optimum: the study's paper-score optimum, worker frame [m].
        evaluator: the twin (default: the default worker and box).
    """
    evaluator = evaluator or Evaluator()
    body = evaluator.body
    where = locations(evaluator, optimum)
    names = list(where)
    table = evaluate(np.stack([where[n] for n in names]), evaluator, joints=True)
    rows = []
    for c in CONDITIONS:
        row = table.iloc[names.index(c.location)]
        feasible = bool(row["feasible"])
        twin = float(MEASURES[c.measure](row, body)) if feasible else NAN
        rows.append({
            "source": c.source, "condition": c.condition, "quantity": c.quantity,
            "published": c.published, "published_sd": c.published_sd, "low": c.low,
            "high": c.high, "basis": c.basis, "location": c.location,
            "box_x": row["x"], "box_y": row["y"], "box_z": row["z"],
            "twin": twin, "twin_note": "" if feasible else f"infeasible: {row['reason']}",
            "within": bool(feasible and c.low <= twin <= c.high),
        })
    return pd.DataFrame(rows)


LOW_BOX_WORKERS = ("p5-female", "p50-female", "p50-male", "p95-male")
LEG_JOINTS = ("ankle_flexion", "knee_flexion", "hip_flexion", "lumbar_flexion")
LOW_BOX_HEIGHTS = (1.0, 0.75)  # fractions of the worker's knee height


def knee_height_postures(task, workers: tuple[str, ...] = LOW_BOX_WORKERS) -> pd.DataFrame:
    """The legs and back of each worker at the ``body`` boundary's lowest row (knee height)
    and a quarter below it.

    Per worker and height (:data:`LOW_BOX_HEIGHTS`), three x by four z locations across the
    boundary; per location its knee, hip, lumbar and ankle flexion [deg] and the postural index,
    knee flexion over ankle + hip + lumbar flexion (~0 a stoop, ~1 a full squat;
    Burgess-Limerick & Abernethy 1997).
    """
    rows = []
    for name in workers:
        evaluator = Evaluator(BodySpec.from_percentile(name), task)
        box = Boundary.from_body(evaluator.body, task)
        points = np.array([[x, box.y[0] * f, z] for f in LOW_BOX_HEIGHTS
                           for x in np.linspace(*box.x, 3) for z in np.linspace(*box.z, 4)])
        table = evaluate(points, evaluator, joints=True)
        deg = {j: np.degrees(table[f"q_{j}"].to_numpy()) for j in LEG_JOINTS}
        bend = deg["ankle_flexion"] + deg["hip_flexion"] + deg["lumbar_flexion"]
        rows.append(pd.DataFrame({
            "worker": name, "stature_m": evaluator.body.stature_m,
            "knee_height_fraction": np.repeat(LOW_BOX_HEIGHTS, len(points) // 2),
            "x": table["x"],
            "y": table["y"], "z": table["z"], "feasible": table["feasible"],
            **{j: deg[j] for j in LEG_JOINTS}, "postural_index": deg["knee_flexion"] / bend}))
    return pd.concat(rows, ignore_index=True)
