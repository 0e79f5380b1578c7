"""How well each keypoint format measures a worker: the twin's own handover postures placed as
each format places its joints, measured back by the capture layer, and scored with published
angle errors added.

- **Columns** (:func:`column_table`): per format and Posture angle column, the share of the
  postures in which the format measures it and, where it does, how far the measured angle lies
  from the twin's (the format's own definition against the twin's: 0 for formats with a spine
  point and a neck base; the mid-hip to mid-shoulder trunk of COCO-17 and MediaPipe is not the
  twin's thorax).
- **Scores** (:func:`score_table`): per format, angle error and score, how often the score comes
  out right when every measured angle carries independent Gaussian error of that SD (the
  unseen columns giving an interval, the task factors known): *right* when the interval is one
  value and it is the twin's error-free score, *holds* when the interval holds it. The SDs are
  published accuracies of the inputs users bring (the study's config cites them).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...capture import FORMATS, capture, capture_scores
from ...capture.angles import clavicle_slope_deg
from ...capture.placement import place
from ...capture.unseen import SCORES
from ...ergonomics import Posture, score_postures
from ...ergonomics.posture import COLUMN_BY_NAME, POSTURE_COLUMNS
from ...twin.angles import posture_columns
from ...twin.evaluate import Evaluator, evaluate, joint_angles
from ...twin.kinematics import KinematicModel
from ...twin.skeleton import build_skeleton

TASK = ("load_kg", "coupling", "activity")
"""The task factors keypoints cannot show: given as known, the twin's."""
ANGLES = tuple(c for c in POSTURE_COLUMNS if COLUMN_BY_NAME[c].kind == "angle")


def twin_postures(evaluator: Evaluator, locations: np.ndarray):
    """The twin's solved postures at the feasible ones of ``locations``: their forward
    kinematics and Posture columns."""
    table = evaluate(locations, evaluator, joints=True)
    table = table[table["feasible"] == 1]
    model = KinematicModel(build_skeleton(evaluator.body))
    state = model.forward(joint_angles(table))
    return state, posture_columns(state, evaluator.task, evaluator.trunk_reference)


def column_table(evaluator: Evaluator, state, truth: dict[str, np.ndarray]) -> pd.DataFrame:
    """Per format and angle column: the share measured and the error where measured [deg]."""
    rows = []
    neutral = clavicle_slope_deg(evaluator.body)  # the twin's own body's shoulders at rest
    for name, fmt in FORMATS.items():
        found = capture(place(state, evaluator.body, fmt), fmt, neutral=neutral)
        for column in ANGLES:
            seen = ~found.unseen[:, POSTURE_COLUMNS.index(column)]
            error = np.abs((found.columns[column][seen] - truth[column][seen] + 180.0) % 360.0
                           - 180.0)
            rows.append({"format": name, "column": column, "postures": len(seen),
                         "measured": seen.mean(),
                         "max_error_deg": error.max() if seen.any() else np.nan,
                         "p95_error_deg": np.percentile(error, 95) if seen.any() else np.nan})
    return pd.DataFrame(rows)


def score_table(evaluator: Evaluator, state, truth: dict[str, np.ndarray],
                angle_sds: tuple[float, ...], draws: int, seed: int) -> pd.DataFrame:
    """Per format, angle error SD and score: right, holds and the interval's mean width, with
    95 % intervals over postures (each posture measured ``draws`` times)."""
    true = score_postures(Posture(truth), evaluator.scoring, names=SCORES)
    task = {name: float(truth[name][0]) for name in TASK}
    n = len(truth["trunk_flexion"])
    rows = []
    neutral = clavicle_slope_deg(evaluator.body)
    for name, fmt in FORMATS.items():
        exact = capture(place(state, evaluator.body, fmt), fmt, assume=task, neutral=neutral)
        for sd in angle_sds:
            rng = np.random.default_rng([seed, len(rows)])
            columns = {c: np.repeat(v, draws) for c, v in exact.columns.items()}
            for column in ANGLES:  # unseen ones stay unseen: only their interval counts
                noisy = columns[column] + rng.normal(0.0, sd, n * draws)
                columns[column] = (noisy + 180.0) % 360.0 - 180.0
            measured = type(exact)(columns, np.repeat(exact.unseen, draws, axis=0))
            scores = capture_scores(measured, evaluator.scoring)
            for score in SCORES:
                want = np.repeat(true[score], draws)
                lo, hi = scores[f"{score}_lo"], scores[f"{score}_hi"]
                right = ((lo == hi) & (lo == want)).reshape(n, draws).mean(axis=1)
                holds = ((lo <= want) & (want <= hi)).reshape(n, draws).mean(axis=1)
                width = (hi - lo).reshape(n, draws).mean(axis=1)
                rows.append({"format": name, "angle_sd_deg": sd, "score": score,
                             "postures": n, "draws": draws,
                             **_mean_ci("right", right), **_mean_ci("holds", holds),
                             "mean_width": width.mean()})
    return pd.DataFrame(rows)


def _mean_ci(name: str, per_posture: np.ndarray) -> dict[str, float]:
    """The mean over postures and its normal 95 % interval (postures are the units)."""
    mean = per_posture.mean()
    half = 1.96 * per_posture.std(ddof=1) / np.sqrt(len(per_posture))
    return {name: mean, f"{name}_ci_low": max(mean - half, 0.0),
            f"{name}_ci_high": min(mean + half, 1.0)}
