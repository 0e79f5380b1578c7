"""An accommodation zone for handover risk: for each handover location, the share of a workforce
whose posture there is acceptable — REBA and RULA both at or below their limits — when each
worker's posture is measured as a site would measure it.

For one worker (:func:`accommodated`) the twin solves every location; each feasible posture is
measured ``draws`` times under the measured error model
(:data:`~ergohandover.robustness.measured_error.MEASURED_ERROR`, the same draws at every
location of that worker: common random numbers), and the worker's chance of an acceptable
posture there is the share of those measurements with REBA <= ``reba_max`` and RULA <=
``rula_max``. A location the twin cannot take serves nobody. The workforce's share at a
location is the mean over workers; its interval is the percentile bootstrap over workers.

The zone is every location whose share reaches the stated share; the largest box is the
axis-aligned box of grid cells with the most cells, every one in the zone (:func:`largest_box`).
"""

from __future__ import annotations

import numpy as np

from ...ergonomics import Posture, score_postures
from ...ergonomics.posture import POSTURE_COLUMNS
from ...robustness.measured_error import MEASURED_ERROR
from ...robustness.posture_error import measured_alike
from ...twin.evaluate import Evaluator, evaluate_arrays
from ...workload.strength import load_shares


def accommodated(job: tuple) -> dict[str, np.ndarray]:
    """One worker at every point: ``feasible``, ``reba`` and ``rula`` (error-free; -1 where
    infeasible), ``exact`` (both within the limits, error-free), ``chance`` (the share of
    measured postures within them) and each joint's load as a share of its strength
    (``shoulder_share``, ``elbow_share``, ``trunk_share``: the box in the hands,
    :func:`~ergohandover.workload.strength.load_shares`; NaN where infeasible). ``job`` is
    (evaluator, points, reba_max, rula_max, draws, seed sequence)."""
    evaluator, points, reba_max, rula_max, draws, seed = job
    evaluator: Evaluator
    rows = evaluate_arrays(points, evaluator)
    feasible = rows["flags"] == 0
    n = int(feasible.sum())
    posture = Posture({c: np.asarray(rows[c], dtype=float)[feasible] for c in POSTURE_COLUMNS})
    exact = score_postures(posture, evaluator.scoring, names=("reba", "rula"))
    errors = MEASURED_ERROR.errors(draws, np.random.default_rng(seed))
    scored = score_postures(measured_alike(posture, errors, draws), evaluator.scoring,
                            names=("reba", "rula"))
    within = (scored["reba"] <= reba_max) & (scored["rula"] <= rula_max)
    out = {"feasible": feasible, "reba": np.full(len(points), -1, np.int8),
           "rula": np.full(len(points), -1, np.int8), "exact": np.zeros(len(points), bool),
           "chance": np.zeros(len(points), np.float32)}
    out["reba"][feasible], out["rula"][feasible] = exact["reba"], exact["rula"]
    out["exact"][feasible] = (exact["reba"] <= reba_max) & (exact["rula"] <= rula_max)
    out["chance"][feasible] = within.reshape(n, draws).mean(axis=1)
    for joint, share in load_shares(posture, evaluator.body).items():
        out[f"{joint}_share"] = np.full(len(points), np.nan, np.float32)
        out[f"{joint}_share"][feasible] = share
    return out


def shares(chance: np.ndarray, rng: np.random.Generator, resamples: int,
           level: float = 0.95) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The workforce's share at each location (mean over the rows of ``chance``, workers x
    locations) and its percentile-bootstrap interval over workers: (share, low, high)."""
    workers = chance.shape[0]
    weights = rng.multinomial(workers, np.full(workers, 1.0 / workers), size=resamples)
    resampled = (weights.astype(np.float32) / workers) @ chance.astype(np.float32)
    tail = (1.0 - level) / 2.0
    low, high = np.quantile(resampled, [tail, 1.0 - tail], axis=0)
    return chance.mean(axis=0), low, high


def largest_box(inside: np.ndarray) -> tuple[slice, slice, slice] | None:
    """The axis-aligned box of cells with the most cells, all ``inside`` (a boolean array of
    the grid's shape); None when no cell is. Ties go to the first in (x, y, z) order."""
    if not inside.any():
        return None
    # Cells inside any box [a, b) on each axis, by a 3-D prefix sum.
    total = np.zeros(tuple(n + 1 for n in inside.shape), dtype=np.int64)
    total[1:, 1:, 1:] = inside.cumsum(0).cumsum(1).cumsum(2)
    spans = [np.array([(a, b) for a in range(n) for b in range(a + 1, n + 1)])
             for n in inside.shape]
    xa, xb = spans[0][:, 0][:, None, None], spans[0][:, 1][:, None, None]
    ya, yb = spans[1][:, 0][None, :, None], spans[1][:, 1][None, :, None]
    za, zb = spans[2][:, 0][None, None, :], spans[2][:, 1][None, None, :]
    count = (total[xb, yb, zb] - total[xa, yb, zb] - total[xb, ya, zb] - total[xb, yb, za]
             + total[xa, ya, zb] + total[xa, yb, za] + total[xb, ya, za] - total[xa, ya, za])
    volume = (xb - xa) * (yb - ya) * (zb - za)
    full = np.where(count == volume, volume, 0)
    i, j, k = np.unravel_index(int(np.argmax(full)), full.shape)
    return tuple(slice(int(s[m, 0]), int(s[m, 1])) for s, m in zip(spans, (i, j, k),
                                                                      strict=True))
