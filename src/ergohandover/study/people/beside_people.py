"""The twin beside Kim et al.'s 1,000 measured human-human handovers (ICRA 2025).

The measured side is ``measured_handovers.csv``: figures derived from the data set by
``experiments/tools/derive_measured_handovers.py`` (the data stay outside the project). Per
handover, at the transfer: where the receiver took the object, relative to their feet, pelvis,
elbow and shoulder; the receiver's tracked segment lengths and standing shoulder height; their
posture through the capture layer and its scores (intervals where ZED BODY_34 cannot see).

Three comparisons, each per handover:

* **where people received**: the object's and the receiving hand's place, also per stature;
* **the twin's prediction**: the twin sized to that receiver
  (:func:`~ergohandover.twin.segment_sizing.body_from_segments` from the tracked thigh, shank,
  upper arm and forearm and the standing shoulder height), its receiving hand's grip put where
  the receiver's hand point was, holding a light object in that hand
  (:data:`~ergohandover.twin.task.OBJECTS`, the data set does not say what was handed), solves
  its posture from standing as the solver's lattice nodes are solved. One definition of each
  angle on both sides: the twin's points are placed as ZED BODY_34 keypoints and measured by
  the capture layer as the receiver's were, and trunk, neck and knee flexion are read from each
  side's own neutral (:data:`CALIBRATED`). Against predictors that need no twin:
  :mod:`.skill`;
* **the recommendation against people**: the optimum of the twin sized to the median receiver
  for the same one-handed task, beside where people's hands were; the twin's scores where
  people received beside people's own measured scores.

The receivers cannot be told apart (the tracker's skeleton has fixed proportions and the data
set names nobody), so a fit of the solver's weights (:func:`fit`) is trained on a seeded half of
the in-distribution recordings and held out on the other half and on the out-of-distribution
ones: the held-out handovers may share receivers with the training ones.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

from ...capture import capture, keypoint_format
from ...capture.placement import place
from ...ergonomics import Posture, score_postures
from ...frames import world_to_worker
from ...twin.angles import posture_columns
from ...twin.anthropometry import BodySpec
from ...twin.segment_sizing import body_from_segments
from ...twin.solver import PostureSolver, SolverSettings
from ...twin.task import TaskSpec

MEASURED = Path(__file__).with_name("measured_handovers.csv")
ANGLES = ("trunk_flexion", "neck_flexion", "knee_flexion", "upper_arm_flexion",
          "upper_arm_abduction", "elbow_flexion")
"""The angles compared: the receiving side's for the limbs. Measured by ZED BODY_34 in every
handover (its wrists and shoulder girdle are held rigid by the tracker: not compared)."""
SIDED = ("knee_flexion", "upper_arm_flexion", "upper_arm_abduction", "elbow_flexion")
COMPARED = tuple(f"{side}_{angle}" if angle in SIDED else angle
                 for angle in ANGLES for side in (("left", "right") if angle in SIDED else ("",)))
"""The Posture columns the angles are read from (both sides of the sided ones)."""
SCORES = ("reba", "rula", "paper_postural")
CALIBRATED = ("trunk_flexion", "neck_flexion", "knee_flexion")
"""The angles read from each side's own neutral: the recording's median over its standing frames,
the twin's upright posture (every joint at zero), both through the same keypoints. The arms'
angles are not: in the standing frames the arms swing or carry, which is no neutral."""
TRACKER = keypoint_format("zed34")
"""The keypoints both sides are read through: ZED BODY_34, as the data set was tracked."""


def source() -> str:
    """The data set's citation, the derived file's first line."""
    with MEASURED.open() as handle:
        return handle.readline().removeprefix("# source:").strip()


def measured_handovers(path: Path = MEASURED) -> tuple[pd.DataFrame, pd.Series]:
    """The handovers used (one row each, with ``kind``: in- or out-of-distribution) and the
    number dropped per reason."""
    table = pd.read_csv(path, comment="#", keep_default_na=False, na_values=[""])
    dropped = table["dropped"].notna()
    used = table[~dropped].drop(columns="dropped").reset_index(drop=True)
    used["kind"] = np.where(used["handover"].str.startswith("motion_variation"),
                            "out-of-distribution", "in-distribution")
    return used, table.loc[dropped, "dropped"].value_counts()


def split(used: pd.DataFrame, train_share: float, seed: int) -> np.ndarray:
    """Each handover's split: ``train`` (a seeded share of the in-distribution recordings),
    ``held-out`` (the rest of them) or ``out-of-distribution``."""
    inside = np.flatnonzero(used["kind"] == "in-distribution")
    rng = np.random.default_rng(seed)
    train = rng.choice(inside, round(train_share * len(inside)), replace=False)
    out = np.where(used["kind"] == "in-distribution", "held-out", "out-of-distribution")
    out[train] = "train"
    return out


def receiver_body(row) -> BodySpec:
    """The twin sized to one receiver: tracked segment lengths and standing shoulder height."""
    return body_from_segments(
        {"thigh": row.thigh_m, "shank": row.shank_m, "upper_arm": row.upper_arm_m,
         "forearm": row.forearm_m}, shoulder_height_m=round(row.shoulder_height_m, 3))


def hand_points(used: pd.DataFrame) -> np.ndarray:
    """(N, 3) each receiving hand's point at the transfer, worker frame [m]."""
    # The derived figures' forward, left, up are the world frame's axes (x forward, y left).
    return world_to_worker(used[["hand_forward_m", "hand_lateral_m", "hand_height_m"]]
                           .to_numpy(float))


def predict(used: pd.DataFrame, bodies: list[BodySpec], task: TaskSpec,
            settings: SolverSettings | None = None) -> pd.DataFrame:
    """The twin's posture for each handover: sized as ``bodies``, the receiving hand's grip at
    the receiver's hand point, solved from standing for ``settings.lattice_iterations``.

    Returns one row per handover: ``hand_error_m``; the twin's :data:`ANGLES` (the receiving
    side's) as the tracker reads them (:func:`tracked_angles`: its points placed as ZED BODY_34
    and measured as people's were, :data:`CALIBRATED` from its upright posture), each also as
    ``own_*``, the twin's own definition; and its scores (its own posture's)."""
    settings = settings or SolverSettings()
    points = hand_points(used)
    postures, placed, upright, hand_error = [], [], [], []
    for k, (body, hand) in enumerate(zip(bodies, used["receiving_hand"], strict=True)):
        solver = PostureSolver(body, replace(task, hands=hand), settings)
        start = solver.strategy_start("stoop")[None]
        solution = solver.iterate(points[k:k + 1], start, settings.lattice_iterations)
        postures.append(posture_columns(solution.state, solver.task))
        placed.append(place(solution.state, body, TRACKER, up="z")[0])
        upright.append(place(solver.model.forward(np.zeros((1, solver.model.nq))), body,
                             TRACKER, up="z")[0])
        hand_error.append(float(solution.hand_error[0]))
    left = used["receiving_hand"].to_numpy() == "left"
    own = {name: np.concatenate([p[name] for p in postures]) for name in postures[0]}
    scores = score_postures(Posture(own), names=SCORES)  # every handover at once
    return pd.concat([tracked_angles(np.stack(placed), np.stack(upright), left),
                      pd.DataFrame({"hand_error_m": hand_error,
                                    **{f"own_{angle}": on_receiving_side(own, left, angle)
                                       for angle in ANGLES},
                                    **{score: scores[score].astype(int) for score in SCORES}})],
                     axis=1)


def side_column(angle: str, hand: str) -> str:
    """The Posture column of one of :data:`ANGLES` on the receiving ``hand``'s side."""
    return f"{hand}_{angle}" if angle in SIDED else angle


def on_receiving_side(columns, left: np.ndarray, angle: str, prefix: str = "") -> np.ndarray:
    """(N,) column ``prefix`` + one of :data:`ANGLES` on each handover's receiving side, from
    ``columns`` (a table or a dict of arrays; ``left``: (N,) bool, the left hand received)."""
    return np.where(left, columns[prefix + side_column(angle, "left")],
                    columns[prefix + side_column(angle, "right")]).astype(float)


def tracked_angles(points: np.ndarray, neutral: np.ndarray, left: np.ndarray) -> pd.DataFrame:
    """:data:`ANGLES` (the receiving side's; ``left``: (N,) bool, the left hand received) of
    (N, 34, 3) ZED BODY_34 points (z up), as the capture layer measures them,
    :data:`CALIBRATED` less their value in the (N, 34, 3) ``neutral`` points [deg]."""
    at, zero = capture(points, TRACKER, "z").columns, capture(neutral, TRACKER, "z").columns
    return pd.DataFrame({angle: on_receiving_side(at, left, angle) - (
        on_receiving_side(zero, left, angle) if angle in CALIBRATED else 0.0)
        for angle in ANGLES})


def measured_angles(used: pd.DataFrame, calibrated: bool = True) -> pd.DataFrame:
    """The receivers' :data:`ANGLES` (the receiving side's) [deg]; :data:`CALIBRATED` less the
    recording's own neutral (``neutral_*``: its median over its standing frames) unless
    ``calibrated`` is False."""
    return pd.DataFrame({angle: receiving_side(used, angle) - (
        receiving_side(used, angle, "neutral_") if calibrated and angle in CALIBRATED else 0.0)
        for angle in ANGLES})


def receiving_side(used: pd.DataFrame, angle: str, prefix: str = "") -> np.ndarray:
    """(N,) column ``prefix + angle`` of each handover's receiving side."""
    return on_receiving_side(used, used["receiving_hand"].to_numpy() == "left", angle, prefix)


def fit_loss(measured: pd.DataFrame, predicted: pd.DataFrame) -> float:
    """The fit's objective: the RMSE over every angle of every handover [deg]."""
    diff = (predicted[list(ANGLES)].to_numpy() - measured[list(ANGLES)].to_numpy()).ravel()
    return float(np.sqrt(np.nanmean(diff ** 2)))


def fitted_settings(factors: dict[str, float], base: SolverSettings) -> SolverSettings:
    """``base`` with the fitted weights: ``gaze`` a factor on the gaze weight, every other name
    a factor on that joint's preference weight."""
    joints = tuple((name, round(value, 4)) for name, value in factors.items() if name != "gaze")
    gaze = base.gaze * factors.get("gaze", 1.0)
    return replace(base, joint_preference_scales=joints, gaze=round(gaze, 4))


def fit(used: pd.DataFrame, bodies: list[BodySpec], task: TaskSpec, names: tuple[str, ...],
        evaluations: int, progress=print) -> tuple[dict[str, float], list[dict]]:
    """Fit the factors on ``names`` (each 0.1-10, searched in log space by Powell's method
    from 1, deterministic) to the handovers given, minimising :func:`fit_loss`.

    Returns the best factors and the history (one row per evaluation: factors and loss)."""
    from scipy.optimize import minimize  # only the fit needs it

    measured = measured_angles(used)
    history: list[dict] = []

    def loss(logs: np.ndarray) -> float:
        factors = dict(zip(names, np.round(np.exp(np.clip(logs, -math.log(10), math.log(10))),
                                           4), strict=True))
        value = fit_loss(measured, predict(used, bodies, task,
                                           fitted_settings(factors, SolverSettings())))
        history.append({**factors, "loss_deg": round(value, 4)})
        if len(history) % 10 == 0:
            progress(f"  fit: {len(history)} evaluations, best RMSE "
                     f"{min(h['loss_deg'] for h in history):.2f} deg")
        return value

    bounds = [(-math.log(10), math.log(10))] * len(names)
    minimize(loss, np.zeros(len(names)), method="Powell", bounds=bounds,
             options={"maxfev": evaluations, "xtol": 0.02, "ftol": 1e-4})
    best = min(history, key=lambda h: h["loss_deg"])
    return {name: best[name] for name in names}, history


LOCATIONS = {
    "object height above the floor [m]": "height_m",
    "object above the receiving elbow [m]": "above_elbow_m",
    "object above the receiving shoulder [m]": "above_shoulder_m",
    "object forward of the feet [m]": "forward_m",
    "object forward of the pelvis [m]": "forward_of_pelvis_m",
    "object to the receiving side of the feet [m]": "side_m",
    "hand height above the floor [m]": "hand_height_m",
    "hand forward of the feet [m]": "hand_forward_m",
    "hand to the receiving side of the feet [m]": "hand_side_m",
    "object height per stature [1]": "height_per_stature",
    "object forward of the feet per stature [1]": "forward_per_stature",
}
"""The receiving-location statistics: label -> column of :func:`location_columns`."""


def location_columns(used: pd.DataFrame, statures: np.ndarray) -> pd.DataFrame:
    """Per handover, every quantity of :data:`LOCATIONS`; lateral offsets toward the
    receiving hand's side (positive: on that side), per stature with the twin's stature."""
    toward = np.where(used["receiving_hand"] == "left", 1.0, -1.0)  # left is +lateral
    out = used[["height_m", "above_elbow_m", "above_shoulder_m", "forward_m",
                "forward_of_pelvis_m", "hand_height_m", "hand_forward_m"]].copy()
    out["side_m"] = toward * used["lateral_m"]
    out["hand_side_m"] = toward * used["hand_lateral_m"]
    out["height_per_stature"] = used["height_m"] / statures
    out["forward_per_stature"] = used["forward_m"] / statures
    return out


def location_table(columns: pd.DataFrame) -> pd.DataFrame:
    """Per quantity of :data:`LOCATIONS`: N, median, quartiles and the 5th and 95th
    percentiles."""
    rows = []
    for label, column in LOCATIONS.items():
        values = columns[column].dropna().to_numpy()
        p5, p25, p50, p75, p95 = np.percentile(values, [5, 25, 50, 75, 95])
        rows.append({"quantity": label, "column": column, "n": values.size,
                     "median": round(p50, 3), "p25": round(p25, 3), "p75": round(p75, 3),
                     "p5": round(p5, 3), "p95": round(p95, 3)})
    return pd.DataFrame(rows)


def receiving_points(used: pd.DataFrame) -> np.ndarray:
    """(N, 3) the receiving hands' points as if every receiver took with the right hand (a
    left hand's mirrored), worker frame [m]: where the one-handed optimum is compared."""
    points = hand_points(used)
    points[used["receiving_hand"].to_numpy() == "left", 0] *= -1.0
    return points


NULL_SHIFT_M = 0.10
"""How far the null moves every receiving hand, in a random direction."""


def recommendation(landscape, people: np.ndarray, twin_scores: pd.DataFrame,
                   used: pd.DataFrame, rng: np.random.Generator) -> pd.DataFrame:
    """Per score: the twin's one-handed optimum (the most symmetric minimiser, and how many
    cells share the minimum), how far each receiving hand was from the nearest minimiser
    (median and quartiles; the share within one grid step, and that share's null: every hand
    moved :data:`NULL_SHIFT_M` in a random direction drawn from ``rng``), the twin's own score
    where people received (median; the share at its optimum) and people's measured score there
    (median of the interval's ends; the share whose interval holds the twin's optimum
    value)."""
    from scipy.spatial import cKDTree  # the nearest minimiser of many

    from ...landscape.stats import optimum

    rows = []
    step = landscape.grid.step
    direction = rng.normal(size=people.shape)
    moved = people + NULL_SHIFT_M * direction / np.linalg.norm(direction, axis=1, keepdims=True)
    for score in SCORES:
        cells, best = optimum(landscape, score)
        value = int(landscape.arrays[score][cells[0]])
        tree = cKDTree(landscape.grid.coordinates(cells))
        distance, _ = tree.query(people)
        null, _ = tree.query(moved)
        to_best = np.linalg.norm(people - best, axis=1)
        lo, hi = used[f"{score}_lo"].to_numpy(), used[f"{score}_hi"].to_numpy()
        twin = twin_scores[score].to_numpy()
        rows.append({
            "score": score, "optimum": value, "optimum_cells": len(cells),
            "optimum_x": round(best[0], 3), "optimum_y": round(best[1], 3),
            "optimum_z": round(best[2], 3), "n": len(people),
            "distance_median_m": round(float(np.median(distance)), 3),
            "distance_p25_m": round(float(np.percentile(distance, 25)), 3),
            "distance_p75_m": round(float(np.percentile(distance, 75)), 3),
            "within_step_share": round(float(np.mean(distance <= step + 1e-9)), 4),
            "within_step_null_share": round(float(np.mean(null <= step + 1e-9)), 4),
            "to_most_symmetric_median_m": round(float(np.median(to_best)), 3),
            "twin_there_median": float(np.median(twin)),
            "twin_there_at_optimum_share": round(float(np.mean(twin == value)), 4),
            "people_lo_median": float(np.median(lo)), "people_hi_median": float(np.median(hi)),
            "people_hold_optimum_share": round(float(np.mean((lo <= value) & (value <= hi))),
                                               4)})
    return pd.DataFrame(rows)
