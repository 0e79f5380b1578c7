"""The statistics of the learning study: success rates with Wilson intervals, evaluations to
the target with censored runs kept, best-so-far curves with bootstrap bands, and paired
comparisons of agents with Holm's correction, an equivalence test and their power.

A run that never reaches the target within its budget is *censored*: it is counted as a
failure and ranks after every run that did reach it, never dropped.

Runs are *paired*: run r of a target has one seed for every agent (common random numbers), so
two agents are compared run for run — Wilcoxon's signed-rank test on evaluations to the target
and McNemar's exact test on success (statsmodels, scipy). Success rates are called equivalent
within a margin M by two one-sided tests (TOST) that use the pairing: "agent a succeeds in at
least M more of the runs than b" implies that the runs where only a succeeds are at least a
share M of all, so an exact binomial test that rejects the latter rejects the former; likewise
for b. The larger of the two one-sided p-values is the TOST's. It is exact at any number of
runs and strongest where the agents agree run for run (docs/learning.md says why not a t-TOST
on 0/1 indicators, whose variance is 0 when every pair agrees, nor the two-independent-samples
score TOST, whose p-value cannot fall below 4e-4 with 100 runs a side).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats
from statsmodels.stats.contingency_tables import mcnemar
from statsmodels.stats.multitest import multipletests
from statsmodels.stats.power import TTestPower
from statsmodels.stats.proportion import binom_test, proportion_confint

WILCOXON_EFFICIENCY = 0.864
"""The lowest asymptotic relative efficiency of Wilcoxon's signed-rank test to the paired
t-test over continuous distributions (Hodges & Lehmann 1956): its power at n runs is at least
the t-test's at 0.864 n, which is how :func:`power_table` bounds it."""


def wilson(successes: int, n: int, alpha: float = 0.05) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion (95 % by default; statsmodels)."""
    if n == 0:
        return math.nan, math.nan
    low, high = proportion_confint(successes, n, alpha=alpha, method="wilson")
    # At 0 or n successes one end is exactly 0 or 1 (the formula leaves a rounding residue).
    return (0.0 if successes == 0 else float(low)), (1.0 if successes == n else float(high))


def censored_median(evaluations: np.ndarray) -> float:
    """Median evaluations-to-target with censored runs (NaN) ranked last: defined only when
    more than half of the runs reached the target (else NaN: "more than the budget")."""
    values = np.sort(np.where(np.isnan(evaluations), np.inf, evaluations))
    median = float(np.median(values))
    return median if math.isfinite(median) else math.nan


def cliffs_delta(a: np.ndarray, b: np.ndarray) -> float:
    """P(a < b) − P(a > b) over all pairs: +1 when every run of ``a`` reached the target
    sooner than every run of ``b`` (censored runs, NaN, count as never). Unpaired; no library
    computes it."""
    a = np.where(np.isnan(a), np.inf, a)[:, None]
    b = np.where(np.isnan(b), np.inf, b)[None, :]
    return float((a < b).mean() - (a > b).mean())


def paired_comparison(a: np.ndarray, b: np.ndarray, budget: float, margin: float) -> dict:
    """Agent ``a`` against ``b`` run for run (element i of both had the same seed).

    Args:
        a, b: (n,) evaluations to the target, NaN where the run never reached it.
        budget: the budget [evaluations]: a censored run ranks as ``budget + 1``, after every
            run that reached the target.
        margin: the equivalence margin on the success rates (0.1: ±10 percentage points).

    Returns:
        ``n``; ``p_wilcoxon`` (two-sided signed-rank test on evaluations to the target, pairs
        with equal values dropped; 1 when every pair is equal); ``rank_biserial`` (the
        matched-pairs rank-biserial correlation, the signed-rank test's effect size: +1 when
        ``a`` got there sooner in every pair that differs); ``p_mcnemar`` (exact, on success);
        ``p_tost`` (success rates within ±``margin``: :func:`equivalence_p`).
    """
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    hit_a, hit_b = ~np.isnan(a), ~np.isnan(b)
    ranked_a = np.where(hit_a, a, budget + 1)
    ranked_b = np.where(hit_b, b, budget + 1)
    diff = ranked_a - ranked_b
    differ = diff != 0
    if differ.any():
        p_wilcoxon = float(stats.wilcoxon(ranked_a, ranked_b, zero_method="wilcox").pvalue)
        ranks = stats.rankdata(np.abs(diff[differ]))
        sooner, later = ranks[diff[differ] < 0].sum(), ranks[diff[differ] > 0].sum()
        effect = float((sooner - later) / ranks.sum())
    else:
        p_wilcoxon, effect = 1.0, 0.0
    table = [[int((hit_a & hit_b).sum()), int((hit_a & ~hit_b).sum())],
             [int((~hit_a & hit_b).sum()), int((~hit_a & ~hit_b).sum())]]
    return {"n": len(a), "p_wilcoxon": p_wilcoxon, "rank_biserial": effect,
            "p_mcnemar": float(mcnemar(table, exact=True).pvalue),
            "p_tost": equivalence_p(table[0][1], table[1][0], len(a), margin)}


def equivalence_p(only_a: int, only_b: int, n: int, margin: float) -> float:
    """The TOST p-value of "the success rates of a and b differ by less than ``margin``" from
    paired runs: ``only_a`` runs where only a succeeded, ``only_b`` where only b did, of ``n``.

    Each one-sided null (a's rate at least ``margin`` above b's, or below) implies that the
    runs where only that agent succeeds are at least a share ``margin``; the exact binomial
    test of that share (statsmodels ``binom_test``, alternative ``smaller``) rejects it when
    they are rarer. Exact at any ``n``, conservative when the discordant runs are many but
    balanced (then no test with this many runs shows equivalence within 10 points).
    """
    sides = [binom_test(k, n, prop=margin, alternative="smaller") for k in (only_a, only_b)]
    return float(max(sides))


def holm(p_values) -> np.ndarray:
    """Holm's step-down adjustment over one family of p-values (statsmodels ``multipletests``):
    an adjusted p below α rejects with a family-wise error rate of at most α."""
    p = np.asarray(p_values, dtype=float)
    if p.size == 0:
        return p
    return multipletests(p, method="holm")[1]


def equivalent(margin: float) -> str:
    """The verdict's text for equivalent success rates: ``equivalent within ±10 pp``."""
    return f"equivalent within ±{100 * margin:g} pp"


def verdict(p_wilcoxon_holm: float, effect: float, p_tost_holm: float, margin: float,
            alpha: float = 0.05) -> str:
    """What a comparison says, after Holm's correction: ``better`` or ``worse`` (the
    signed-rank test on evaluations to the target rejects; the effect's sign says which),
    else ``equivalent within ±M pp`` (the TOST on success rates rejects a difference of M or
    more), else ``no conclusion``."""
    if p_wilcoxon_holm < alpha:
        return "better" if effect > 0 else "worse"
    if p_tost_holm < alpha:
        return equivalent(margin)
    return "no conclusion"


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


def signed_rank_power(n: int, effect: float, alpha: float) -> float:
    """A lower bound of the two-sided signed-rank test's power at ``n`` pairs against a
    standardised paired shift ``effect`` (Cohen's d_z): the paired t-test's (statsmodels
    ``TTestPower``) at :data:`WILCOXON_EFFICIENCY` × n pairs, rounded down (its noncentral
    t returns NaN at some fractional degrees of freedom)."""
    pairs = max(2, math.floor(WILCOXON_EFFICIENCY * n))
    return float(TTestPower().power(effect_size=effect, nobs=pairs, alpha=alpha,
                                    alternative="two-sided"))


def _pair_counts(n: int, only_a: float, only_b: float) -> tuple[np.ndarray, np.ndarray,
                                                                np.ndarray]:
    """Every (runs where only a succeeds, runs where only b does) of n paired runs and its
    probability (multinomial), where each run is discordant one way with probability
    ``only_a`` and the other with ``only_b``."""
    k_a, k_b = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    keep = k_a + k_b <= n
    k_a, k_b = k_a[keep], k_b[keep]
    counts = np.stack([k_a, k_b, n - k_a - k_b], axis=1)
    probability = stats.multinomial.pmf(counts, n, [only_a, only_b, 1 - only_a - only_b])
    return k_a, k_b, probability


def mcnemar_power(n: int, only_a: float, only_b: float, alpha: float) -> float:
    """The exact McNemar test's power at ``n`` paired runs: the probability, summed over every
    outcome, that statsmodels' ``mcnemar(exact=True)`` rejects at ``alpha``."""
    k_a, k_b, probability = _pair_counts(n, only_a, only_b)
    likely = probability > 1e-12
    p = np.array([mcnemar([[0, x], [y, 0]], exact=True).pvalue
                  for x, y in zip(k_a[likely], k_b[likely], strict=True)])
    return float(probability[likely][p < alpha].sum())


def tost_power(n: int, discordant: float, margin: float, alpha: float) -> float:
    """The power of :func:`equivalence_p` at ``n`` paired runs when the two agents' success
    rates are equal and a share ``discordant`` of the runs goes each way: the probability that
    both one-sided tests reject at ``alpha``."""
    passes = np.array([binom_test(k, n, prop=margin, alternative="smaller") < alpha
                       for k in range(n + 1)])
    if discordant == 0:
        return float(passes[0])
    k_a, k_b, probability = _pair_counts(n, discordant, discordant)
    return float(probability[passes[k_a] & passes[k_b]].sum())
