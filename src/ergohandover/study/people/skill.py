"""How well each predictor of people's angles does held out, against what needs no model.

Every predictor is fitted on the training split only and read on the held-out and the
out-of-distribution recordings (each recording is one handover, so no recording's frames fall
on both sides):

* **constant**: the training split's mean angle, the floor any model must beat;
* **line**: a straight line in the receiving hand's height, forward and sideways place and the
  receiver's stature (5 parameters per angle);
* **neighbours**: the mean angle of the :data:`NEIGHBOURS` training handovers nearest in those
  four inputs (standardised), a flexible data-driven model, the data's own ceiling for them;
* **twin** and **fitted twin**: the twin's angles as :func:`~.beside_people.predict` reads them,
  with the default and the fitted weights, no parameter fitted to the angles;
* **line + twin**: the line with the twin's angle as a fifth input (6 parameters per angle):
  what the twin adds to where the hand is.

Skill is 1 - MSE(model) / MSE(constant) on the same handovers; its 95 % interval is the
percentile bootstrap over handovers (the two MSEs resampled together). Beside each RMSE stands
the data's noise ceiling: the root mean square of each angle's spread over the frames around the
transfer (``spread_*``), what no predictor of one frame's posture can beat.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .beside_people import ANGLES, receiving_side

INPUTS = ("hand_height_m", "hand_forward_m", "hand_side_m", "stature_m")
"""The line's and the neighbours' inputs (:func:`~.beside_people.location_columns` and the
twin's stature)."""
NEIGHBOURS = 10
GROUPS = ("held-out", "out-of-distribution")
PREDICTORS = ("constant", "line", "neighbours", "twin", "fitted twin", "line + twin")
ALL = "all six"
"""The row pooling every angle of every handover."""


def bootstrap_weights(n: int, rng: np.random.Generator, resamples: int) -> np.ndarray:
    """(resamples, n) multinomial counts: each row one resample of the n handovers."""
    return rng.multinomial(n, np.full(n, 1.0 / n), size=resamples).astype(float)


def inputs(places: pd.DataFrame, statures: np.ndarray) -> np.ndarray:
    """(N, 4) the :data:`INPUTS` of each handover."""
    return np.column_stack([places[c].to_numpy(float) for c in INPUTS[:-1]] + [statures])


def _least_squares(design: np.ndarray, y: np.ndarray, train: np.ndarray) -> np.ndarray:
    """(N,) the fit of ``y`` on ``design`` (with an intercept) over the finite training rows."""
    design = np.column_stack([np.ones(len(design)), design])
    rows = train & np.isfinite(y) & np.isfinite(design).all(axis=1)
    coefficients = np.linalg.lstsq(design[rows], y[rows], rcond=None)[0]
    return design @ coefficients


def predictions(measured: pd.DataFrame, x: np.ndarray, twins: dict[str, pd.DataFrame],
                train: np.ndarray) -> dict[str, np.ndarray]:
    """Each of :data:`PREDICTORS`: (N, len(ANGLES)) predicted angles [deg], fitted on the rows
    ``train`` (bool) of ``measured`` only. ``twins`` holds the "twin" and "fitted twin"
    angles."""
    y = measured[list(ANGLES)].to_numpy(float)
    out = {"constant": np.broadcast_to(np.nanmean(y[train], axis=0), y.shape).copy()}
    out["line"] = np.column_stack([_least_squares(x, y[:, j], train)
                                   for j in range(len(ANGLES))])
    centre, scale = x[train].mean(axis=0), x[train].std(axis=0)
    z = (x - centre) / scale
    distance = ((z[:, None, :] - z[None, train, :]) ** 2).sum(axis=-1)
    # A handover of the training split is not its own neighbour.
    distance[np.flatnonzero(train), np.arange(train.sum())] = np.inf
    nearest = np.argsort(distance, axis=1)[:, :NEIGHBOURS]
    out["neighbours"] = np.nanmean(y[train][nearest], axis=1)
    for name in ("twin", "fitted twin"):
        out[name] = twins[name][list(ANGLES)].to_numpy(float)
    twin = out["twin"]
    out["line + twin"] = np.column_stack([
        _least_squares(np.column_stack([x, twin[:, j]]), y[:, j], train)
        for j in range(len(ANGLES))])
    return out


def ceiling(used: pd.DataFrame) -> pd.DataFrame:
    """(N, len(ANGLES)) each handover's spread of each angle around the transfer [deg]."""
    return pd.DataFrame({angle: receiving_side(used, angle, "spread_") for angle in ANGLES})


def skill_table(measured: pd.DataFrame, predicted: dict[str, np.ndarray], groups: np.ndarray,
                spread: pd.DataFrame, rng: np.random.Generator,
                resamples: int = 2000) -> pd.DataFrame:
    """Per group of :data:`GROUPS`, predictor and angle (and :data:`ALL`): N, RMSE, skill
    against the constant with its 95 % bootstrap interval, bias, and the noise ceiling."""
    y = measured[list(ANGLES)].to_numpy(float)
    rows = []
    for group in GROUPS:
        where = np.flatnonzero(groups == group)
        weights = bootstrap_weights(len(where), rng, resamples)
        base = (predicted["constant"] - y)[where]
        for name in PREDICTORS:
            error = (predicted[name] - y)[where]
            for j, angle in enumerate((*ANGLES, ALL)):
                cols = slice(None) if angle == ALL else slice(j, j + 1)
                e, b = error[:, cols], base[:, cols]
                seen = np.isfinite(e) & np.isfinite(b)
                sq, sq_base = np.where(seen, e, 0.0) ** 2, np.where(seen, b, 0.0) ** 2
                count = seen.sum(axis=1)
                mse = sq.sum() / count.sum()
                skill = 1.0 - mse / (sq_base.sum() / count.sum())
                boot = 1.0 - (weights @ sq.sum(axis=1)) / (weights @ sq_base.sum(axis=1))
                noise = spread.to_numpy(float)[where][:, cols]
                rows.append({
                    "group": group, "predictor": name, "angle": angle,
                    "n": int(count.sum()), "rmse_deg": round(float(np.sqrt(mse)), 2),
                    "skill": round(float(skill), 3),
                    "skill_low": round(float(np.percentile(boot, 2.5)), 3),
                    "skill_high": round(float(np.percentile(boot, 97.5)), 3),
                    "bias_deg": round(float(np.where(seen, e, 0.0).sum() / count.sum()), 2),
                    "ceiling_rmse_deg": round(float(np.sqrt(np.nanmean(noise ** 2))), 2)})
    return pd.DataFrame(rows)
