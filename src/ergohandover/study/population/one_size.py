"""One handover location for everyone, or one per worker? The population study's arithmetic.

Every worker of a workforce has a landscape on one shared grid. From the score matrix (workers
x cells, NaN where the twin cannot take the box) this module picks the one-size locations three
ways — the reference worker's own optimum (what the paper deploys to everyone), the location of
lowest mean score over the workforce, and the one of lowest 95th-percentile score — and measures
each worker's penalty there: the score at the one-size location less the worker's own optimum.
Means carry percentile-bootstrap intervals over workers, shares Wilson intervals; how the
optimum's height scales with body size is an ordinary least-squares line with a bootstrap
interval on its slope.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np
import pandas as pd
from scipy import stats

from ...errors import ConfigError
from ...landscape.stats import most_symmetric
from ...search.statistics import bootstrap_band, wilson
from ..validation.published import CONDITIONS

CHOICES = ("reference", "mean", "p95")
"""The one-size locations: the reference worker's optimum; the lowest mean score over the
workforce; the lowest 95th-percentile score (ties: lowest mean, then the most symmetric)."""
STATURE_BANDS_M = (1.60, 1.70, 1.80)
"""Stature bands of the "who pays" table: below 1.60 m, 1.60-1.70, 1.70-1.80, 1.80 and over."""


def one_size_cells(scores: np.ndarray, points: np.ndarray, reference_cell: int) -> dict[str, int]:
    """The cell of each one-size choice (:data:`CHOICES`).

    Args:
        scores: (W, C) every worker's score at every cell, NaN where infeasible.
        points: (C, 3) the cells' locations, worker frame [m] (for the symmetric tie-break).
        reference_cell: the reference worker's optimum.

    The mean and 95th-percentile choices are taken among cells every worker can take.
    """
    common = common_cells(~np.isnan(scores).any(axis=0))
    values = scores[:, common]
    # The score that 95 % of the workforce is at or below (an observed score, not interpolated).
    p95 = np.quantile(values, 0.95, axis=0, method="inverted_cdf")
    return chosen_cells(common, values.mean(axis=0), p95 == p95.min(), points, reference_cell)


def common_cells(everyone: np.ndarray) -> np.ndarray:
    """The flat indices of the cells every worker can take (``everyone``: (C,) bool); a
    one-line ConfigError when there is none."""
    common = np.flatnonzero(everyone)
    if common.size == 0:
        raise ConfigError("no location of the grid is feasible for every worker of the "
                          "workforce: there is no one-size location to compare")
    return common


def chosen_cells(common: np.ndarray, mean: np.ndarray, lowest_p95: np.ndarray,
                 points: np.ndarray, reference_cell: int) -> dict[str, int]:
    """The one-size choices' rule, from the common cells' mean scores and which of them have
    the lowest 95th percentile: the lowest mean; the lowest 95th percentile, then the lowest
    mean among those; each tie broken by the most symmetric cell."""

    def pick(mask: np.ndarray) -> int:
        cells = common[mask]
        return int(cells[most_symmetric(points[cells])])

    lowest_mean = np.isclose(mean, mean.min(), rtol=0, atol=1e-9)
    tie_mean = np.isclose(mean, mean[lowest_p95].min(), rtol=0, atol=1e-9)
    return {"reference": int(reference_cell), "mean": pick(lowest_mean),
            "p95": pick(lowest_p95 & tie_mean)}


def mean_interval(values: np.ndarray, rng: np.random.Generator,
                  resamples: int) -> tuple[float, float, float]:
    """Mean of ``values`` (NaN dropped) and its 95 % percentile-bootstrap interval."""
    values = values[~np.isnan(values)]
    if values.size == 0:
        return np.nan, np.nan, np.nan
    mean, low, high = bootstrap_band(values[:, None], rng, resamples)
    return float(mean[0]), float(low[0]), float(high[0])


def penalty_summary(penalty: np.ndarray, rng: np.random.Generator, resamples: int) -> dict:
    """The penalties of a group of workers (NaN: the location is infeasible for them): mean
    with its interval, the share penalised (penalty >= 1) and by 2 or more, with Wilson
    intervals, the largest."""
    taken = penalty[~np.isnan(penalty)]
    mean, low, high = mean_interval(taken, rng, resamples)
    out = {"n": int(penalty.size), "infeasible_for": int(np.isnan(penalty).sum()),
           "mean_penalty": mean, "mean_ci_low": low, "mean_ci_high": high}
    for name, bar in (("penalised", 1), ("penalised_2plus", 2)):
        k = int((taken >= bar).sum())
        lo, hi = wilson(k, taken.size)
        out |= {f"share_{name}": k / taken.size if taken.size else np.nan,
                f"share_{name}_ci_low": lo, f"share_{name}_ci_high": hi}
    out["max_penalty"] = float(taken.max()) if taken.size else np.nan
    return out


def stature_band(stature: np.ndarray) -> np.ndarray:
    """The band label of each stature [m] (:data:`STATURE_BANDS_M`)."""
    edges = STATURE_BANDS_M
    labels = [f"< {edges[0]:.2f} m", *(f"{a:.2f}-{b:.2f} m" for a, b in pairwise(edges)),
              f">= {edges[-1]:.2f} m"]
    return np.array(labels, dtype=object)[np.searchsorted(edges, stature, side="right")]


def line_fit(x: np.ndarray, y: np.ndarray, rng: np.random.Generator,
             resamples: int) -> dict:
    """Least-squares line y = intercept + slope x, its R², residual SD and the slope's 95 %
    percentile-bootstrap interval (workers resampled)."""
    fit = stats.linregress(x, y)
    residual = y - (fit.intercept + fit.slope * x)
    picks = rng.integers(len(x), size=(resamples, len(x)))
    xs, ys = x[picks], y[picks]
    xc = xs - xs.mean(axis=1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        slopes = (xc * (ys - ys.mean(axis=1, keepdims=True))).sum(axis=1) / (xc**2).sum(axis=1)
    slopes = slopes[np.isfinite(slopes)]
    return {"n": len(x), "slope": fit.slope, "slope_ci_low": float(np.quantile(slopes, 0.025)),
            "slope_ci_high": float(np.quantile(slopes, 0.975)), "intercept": fit.intercept,
            "r2": fit.rvalue**2, "residual_sd": float(residual.std(ddof=2)),
            "p_slope": fit.pvalue}


def who_pays(table: pd.DataFrame, rng: np.random.Generator, resamples: int) -> pd.DataFrame:
    """Per objective and choice, the penalties of each sex and stature band (``table``: the
    penalties, one row per worker, objective and choice, with ``sex`` and ``stature_m``)."""
    rows = []
    # Sorted by stature, so that the bands come out from the shortest up.
    table = table.assign(band=stature_band(table["stature_m"].to_numpy())).sort_values(
        ["stature_m", "worker"], kind="stable")
    for (objective, choice), part in table.groupby(["objective", "choice"], sort=False):
        for kind, column in (("sex", "sex"), ("stature", "band")):
            for group, rows_of in part.groupby(column, sort=kind == "sex"):
                rows.append({"objective": objective, "choice": choice, "by": kind,
                             "group": group, "mean_stature_m": rows_of["stature_m"].mean(),
                             **penalty_summary(rows_of["penalty"].to_numpy(dtype=float), rng,
                                               resamples)})
    return pd.DataFrame(rows)


def working_heights(below_elbow_cm: np.ndarray) -> pd.DataFrame:
    """How many workers' optima lie in each published working-height range (hand height below
    elbow height, standing work: the validation's sources), with Wilson intervals."""
    n = len(below_elbow_cm)
    rows = []
    for c in CONDITIONS:
        if c.measure != "below_elbow_cm":
            continue
        within = int(((below_elbow_cm >= c.low) & (below_elbow_cm <= c.high)).sum())
        low, high = wilson(within, n)
        rows.append({"source": c.source, "condition": c.condition, "low_cm": c.low,
                     "high_cm": c.high, "n": n, "within": within, "share": within / n,
                     "ci_low": low, "ci_high": high})
    return pd.DataFrame(rows)


def penalty_regression(penalty: np.ndarray, predictors: dict[str, np.ndarray]) -> list[dict]:
    """Ordinary least squares ``penalty ~ 1 + predictors``: each term's coefficient, its
    standard error, 95 % interval and p-value (t, n - terms degrees of freedom); workers
    without a penalty (the twin cannot take the box there) are left out."""
    taken = ~np.isnan(penalty)
    y = penalty[taken]
    x = np.column_stack([np.ones(taken.sum()), *(v[taken] for v in predictors.values())])
    coef, *_ = np.linalg.lstsq(x, y, rcond=None)
    dof = len(y) - x.shape[1]
    sigma2 = ((y - x @ coef) ** 2).sum() / dof
    se = np.sqrt(np.diag(sigma2 * np.linalg.pinv(x.T @ x)))
    t = stats.t.ppf(0.975, dof)
    rows = []
    for name, b, s in zip(("intercept", *predictors), coef, se, strict=True):
        p = 2 * stats.t.sf(abs(b / s), dof) if s > 0 else np.nan
        rows.append({"term": name, "coef": float(b), "se": float(s), "ci_low": float(b - t * s),
                     "ci_high": float(b + t * s), "p": float(p), "n": len(y)})
    return rows
