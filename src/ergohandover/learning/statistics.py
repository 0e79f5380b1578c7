"""The statistics of the learning study: success rates with Wilson intervals, evaluations to
the target with censored runs kept, best-so-far curves with bootstrap bands, and a two-sample
comparison of agents (Mann-Whitney U with Cliff's delta; Fisher's exact test on successes).

A run that never reaches the target within its budget is *censored*: it is counted as a
failure and ranks after every run that did reach it, never dropped.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats

Z95 = 1.959963984540054  # the standard normal's 97.5 % quantile


def wilson(successes: int, n: int, z: float = Z95) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion (95 % by default)."""
    if n == 0:
        return math.nan, math.nan
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    # At 0 or n successes one end is exactly 0 or 1 (the formula leaves a rounding residue).
    low = 0.0 if successes == 0 else max(0.0, centre - half)
    high = 1.0 if successes == n else min(1.0, centre + half)
    return low, high


def censored_median(evaluations: np.ndarray) -> float:
    """Median evaluations-to-target with censored runs (NaN) ranked last: defined only when
    more than half of the runs reached the target (else NaN: "more than the budget")."""
    values = np.sort(np.where(np.isnan(evaluations), np.inf, evaluations))
    median = float(np.median(values))
    return median if math.isfinite(median) else math.nan


def cliffs_delta(a: np.ndarray, b: np.ndarray) -> float:
    """P(a < b) − P(a > b) over all pairs: +1 when every run of ``a`` reached the target
    sooner than every run of ``b`` (censored runs, NaN, count as never)."""
    a = np.where(np.isnan(a), np.inf, a)[:, None]
    b = np.where(np.isnan(b), np.inf, b)[None, :]
    return float((a < b).mean() - (a > b).mean())


def compare(a: np.ndarray, b: np.ndarray) -> dict:
    """Agent ``a`` against ``b`` on evaluations-to-target (NaN = censored).

    Returns:
        ``p_mannwhitney`` (two-sided, censored runs tied last), ``cliffs_delta`` (> 0: ``a``
        sooner), ``p_fisher`` (two-sided, on the success counts).
    """
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    ranked_a = np.where(np.isnan(a), np.inf, a)
    ranked_b = np.where(np.isnan(b), np.inf, b)
    if np.array_equal(np.unique(np.concatenate([ranked_a, ranked_b])), [np.inf]):
        p_rank = 1.0  # nobody reached it: no difference to test
    else:
        p_rank = float(stats.mannwhitneyu(ranked_a, ranked_b, alternative="two-sided").pvalue)
    table = [[int((~np.isnan(a)).sum()), int(np.isnan(a).sum())],
             [int((~np.isnan(b)).sum()), int(np.isnan(b).sum())]]
    return {"p_mannwhitney": p_rank, "cliffs_delta": cliffs_delta(a, b),
            "p_fisher": float(stats.fisher_exact(table).pvalue)}


def best_so_far(steps: np.ndarray, best: np.ndarray, at: np.ndarray) -> np.ndarray:
    """A run's best score after each of ``at`` evaluations, from its trace (improvement
    ``steps`` and the ``best`` score from each on); ``inf`` before the first."""
    index = np.searchsorted(steps, at, side="right") - 1
    return np.where(index >= 0, best[np.maximum(index, 0)], np.inf)


def bootstrap_band(samples: np.ndarray, rng: np.random.Generator, resamples: int = 1000,
                   level: float = 0.95) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean over runs (axis 0) of (runs, points) and its percentile-bootstrap band."""
    n = samples.shape[0]
    picks = rng.integers(n, size=(resamples, n))
    means = samples[picks].mean(axis=1)  # (resamples, points)
    tail = (1 - level) / 2
    return (samples.mean(axis=0), np.quantile(means, tail, axis=0),
            np.quantile(means, 1 - tail, axis=0))
