"""The robustness part's arithmetic: which of the study's comparisons survive posture-measurement
error and a wrong model, the regret of the recommended location, and the population's one-size
locations chosen without optimism.

Definitions (the README and report use these words):
- **survives** (posture error): the 95 % Monte Carlo interval of the difference of expected
  scores (claimed better minus claimed worse) lies below zero; for a penalty (one-size less
  personal), the bootstrap interval over workers lies above zero.
- **regret** of a recommendation in a model variant or for a worker: its score there less that
  variant's or worker's own optimum (the lowest of its grid's minimum and the recommendation's
  own score, so regret is never negative).
- **practice location**: what a practitioner would try first without a model, from two cited
  rules of ergonomics (:data:`PRACTICE`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...landscape import Landscape
from ...landscape.stats import minimum, optimum
from ...robustness.posture_error import ErrorModel, expected_scores, monte_carlo
from ...robustness.search import Search, postures_at, robust_optimum
from ...twin.evaluate import Evaluator, evaluate
from ..population.one_size import CHOICES, one_size_cells
from ..population.resampling import OneSizeResampler
from .config import RobustnessConfig

ROBUST_SCORE = "paper_postural"
"""The score whose robust optimum is sought (the paper's, the study's headline score)."""

PRACTICE_BELOW_ELBOW_M = 0.125
"""Standing light work: hands 10-15 cm below the elbow, the middle of the range (Grandjean E
(1979), Fitting the Task to the Man, Taylor & Francis; as quoted in Magnusson & Ortengren
(1987), Applied Ergonomics 18(2):146-152, p. 148 — the validation part's source)."""
PRACTICE_NEAREST_M = 0.25
"""The hands no nearer than 25 cm in front of the midpoint between the ankles: the revised NIOSH
lifting equation's horizontal multiplier is 1 at H = 25 cm and falls as 25/H beyond (Waters TR,
Putz-Anderson V, Garg A, Fine LJ (1993), Revised NIOSH equation for the design and evaluation of
manual lifting tasks, Ergonomics 36(7):749-776)."""
PRACTICE_STEP_M = 0.01
PRACTICE = (f"{PRACTICE_BELOW_ELBOW_M * 100:g} cm below the elbow (Grandjean 1979), at the "
            f"nearest distance in front from {PRACTICE_NEAREST_M * 100:g} cm (NIOSH, Waters et "
            f"al. 1993) at which the box clears the body, {PRACTICE_STEP_M * 100:g} cm steps")


def practice_location(evaluator: Evaluator, elbow_height_m: float) -> np.ndarray:
    """The practice location of a worker (:data:`PRACTICE`), worker frame [m]; NaNs when the
    box clears the body nowhere within 40 cm further."""
    depths = PRACTICE_NEAREST_M + PRACTICE_STEP_M * np.arange(41)
    points = np.column_stack([np.zeros_like(depths),
                              np.full_like(depths, elbow_height_m - PRACTICE_BELOW_ELBOW_M),
                              depths])
    feasible = evaluate(points, evaluator)["feasible"].to_numpy(bool)
    return np.round(points[np.argmax(feasible)], 6) if feasible.any() else np.full(3, np.nan)


def search_seed(part: RobustnessConfig) -> int:
    """The errors' seed of every robust search of the study (the first of the part's seeds):
    ``ergohandover baseline`` uses it too, so that it finds the study's robust optimum."""
    return int(np.random.SeedSequence(part.seed).spawn(5)[0].generate_state(1)[0])


def robust_recommendation(landscape: Landscape, evaluator: Evaluator, part: RobustnessConfig,
                          seed: int, draws: int, stride: int, keep: int, radius: int,
                          workers: int = 1, tolerance: float | None = None) -> tuple[
                              np.ndarray, Search]:
    """A worker's nominal optimum of :data:`ROBUST_SCORE` (the landscape's) and robust optimum
    at ``part.robust_sd`` of posture error, searched around the nominal one too (so that it is
    never worse in expectation); the search's settings as in :func:`robust_optimum`, which
    ``tolerance`` restricts to cells within it of the error-free optimum."""
    nominal = optimum(landscape, ROBUST_SCORE)[1]
    robust = robust_optimum(landscape, evaluator, ErrorModel(part.robust_sd, part.structure),
                            ROBUST_SCORE, draws, seed, stride, part.screen_draws, keep,
                            radius, workers, include=[landscape.grid.nearest_cell(nominal)],
                            tolerance=tolerance)
    return nominal, robust


def recommendations(landscape: Landscape, evaluator: Evaluator, part: RobustnessConfig,
                    workers: int = 1) -> pd.DataFrame:
    """The nominal and the robust optimum as the study finds them (its search, its seed), each
    scored under ``part.robust_sd`` of posture error: columns ``location`` (``nominal
    optimum``, ``robust optimum``), ``x, y, z, score, angle_sd_deg, nominal, mean,
    p_nominal_or_better, q05, q95, draws``. Raises when the twin cannot take the box there."""
    seed = search_seed(part)
    nominal, robust = robust_recommendation(landscape, evaluator, part, seed, part.draws,
                                            part.stride, part.keep, part.radius, workers)
    where = pd.DataFrame(np.stack([nominal, robust.location]), columns=list("xyz"))
    where.insert(0, "location", ["nominal optimum", "robust optimum"])
    posture, feasible = postures_at(where[list("xyz")].to_numpy(), evaluator)
    if not feasible.all():
        raise RuntimeError(f"the twin cannot take the box at {where[~feasible]}")
    found = monte_carlo(posture, ErrorModel(part.robust_sd, part.structure), part.draws,
                        np.random.default_rng(seed),
                        settings=evaluator.scoring).table(where["location"])
    table = where.merge(found, on="location").assign(angle_sd_deg=part.robust_sd)
    return table[["location", "x", "y", "z", "score", "angle_sd_deg", "nominal", "mean",
                  "p_nominal_or_better", "q05", "q95", "draws"]]


def robust_pair(landscape: Landscape, evaluator: Evaluator, part: RobustnessConfig,
                stride: int, seed: int) -> dict:
    """A worker's nominal and robust locations (a quick search: ``part.worker_draws``, the 8
    best screened cells, 1 cell around) and the robust location among the cells within
    ``part.robust_tolerance`` of the error-free optimum, with the three expected scores under
    the robust SD measured with the same errors: a row of personal.csv."""
    tolerances = {"robust": None, "among_optima": part.robust_tolerance}
    found = {}
    for name, tolerance in tolerances.items():
        nominal, search = robust_recommendation(landscape, evaluator, part, seed,
                                                part.worker_draws, stride, keep=8, radius=1,
                                                tolerance=tolerance)
        found[name] = search.location
    posture, _ = postures_at(np.stack([nominal, *found.values()]), evaluator)
    expected = expected_scores(posture, ErrorModel(part.robust_sd, part.structure),
                               part.worker_draws, seed, settings=evaluator.scoring)
    row = {**{f"nominal_{a}": round(float(v), 6) for a, v in zip("xyz", nominal, strict=True)},
           "nominal_score": minimum(landscape, ROBUST_SCORE), "nominal_expected": expected[0]}
    for k, (name, location) in enumerate(found.items(), start=1):
        score = landscape.arrays[ROBUST_SCORE][landscape.grid.nearest_cell(location)]
        row |= {**{f"{name}_{a}": round(float(v), 6)
                   for a, v in zip("xyz", location, strict=True)},
                f"{name}_score": int(score), f"{name}_expected": expected[k]}
    return row | {"angle_sd_deg": part.robust_sd, "tolerance": part.robust_tolerance,
                  "draws": part.worker_draws}


def difference(a: np.ndarray, b: np.ndarray) -> dict:
    """Two locations' measured scores (draws each, independent): the difference of their
    expected scores with a 95 % Monte Carlo interval, and the chance that one measurement at
    ``a`` comes out lower than (and no higher than) one at ``b``."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    diff = a.mean() - b.mean()
    se = np.sqrt(a.var() / a.size + b.var() / b.size)
    values = np.union1d(a, b)
    pa = (a[:, None] == values).mean(axis=0)
    below_b = np.searchsorted(np.sort(b), values, side="right") / b.size  # P(b <= v)
    return {"difference": diff, "ci_low": diff - 1.96 * se, "ci_high": diff + 1.96 * se,
            "p_lower": float((pa * (1 - below_b)).sum()),
            "p_not_higher": float((pa * (1 - below_b + (b[:, None] == values).mean(axis=0)))
                                  .sum()),
            "survives": bool(diff + 1.96 * se < 0)}


def bootstrap_mean(values: np.ndarray, rng: np.random.Generator,
                   resamples: int) -> tuple[float, float, float]:
    """Mean and 95 % percentile-bootstrap interval (NaN dropped). The same resampling as
    :func:`..population.one_size.mean_interval`, whose quantiles sit at ``(1 - 0.95) / 2``
    (0.025 plus a float's last bit): the committed robustness results were made with these."""
    values = values[~np.isnan(values)]
    means = values[rng.integers(values.size, size=(resamples, values.size))].mean(axis=1)
    return float(values.mean()), float(np.quantile(means, 0.025)), float(np.quantile(means,
                                                                                      0.975))


def regret_rows(source: str, name: str, at: pd.DataFrame, own: dict[str, float],
                recommendations: pd.DataFrame, scores) -> list[dict]:
    """Rows of regret.csv for one variant or worker: ``at`` is its evaluation at the
    recommendations (``recommendations``: ``location, x, y, z``, a row each), ``own`` its grid
    minimum per score."""
    rows = []
    for (_, rec), (_, row) in zip(recommendations.iterrows(), at.iterrows(), strict=True):
        for score in scores:
            value = float(row[score]) if row["feasible"] else np.nan
            best = min(own[score], value) if row["feasible"] else own[score]
            rows.append({"source": source, "variant": name, "recommendation": rec["location"],
                         "x": rec["x"], "y": rec["y"], "z": rec["z"], "score": score,
                         "at_recommendation": value, "own_optimum": best,
                         "regret": value - best})
    return rows


def regret_summary(regret: pd.DataFrame, rng: np.random.Generator,
                   resamples: int) -> pd.DataFrame:
    """Per source, recommendation and score: mean regret (bootstrap 95 %), worst, the share with
    no regret, and how many variants or workers cannot take the box there."""
    rows = []
    for (source, rec, score), part in regret.groupby(["source", "recommendation", "score"],
                                                     sort=False):
        values = part["regret"].to_numpy(float)
        mean, low, high = bootstrap_mean(values, rng, resamples)
        taken = values[~np.isnan(values)]
        rows.append({"source": source, "recommendation": rec, "score": score,
                     "n": len(values), "infeasible": int(np.isnan(values).sum()),
                     "mean_regret": mean, "ci_low": low, "ci_high": high,
                     "max_regret": float(taken.max()), "share_no_regret": float(
                         (taken == 0).mean())})
    return pd.DataFrame(rows)


def penalty_at(scores: np.ndarray, own: np.ndarray, cell: int) -> np.ndarray:
    """(W,) each worker's penalty at a cell (NaN: infeasible for that worker)."""
    return scores[:, cell] - own


def without_optimism(scores: np.ndarray, own: np.ndarray, points: np.ndarray,
                     reference_cell: int, rng: np.random.Generator, resamples: int,
                     splits: int) -> list[dict]:
    """Each one-size choice's mean penalty four ways: in sample (chosen and scored on every
    worker, as the population part reports it); re-chosen inside every bootstrap resample of
    the workers and scored on that resample (optimistic: chosen and scored on the same
    workers) and on the workers the resample left out (out of bag: never on a worker it was
    chosen on); chosen on a random half and scored on the other half (``splits`` times)."""
    w = scores.shape[0]
    chosen = one_size_cells(scores, points, reference_cell)
    resampler = OneSizeResampler(scores, points, reference_cell)
    boot = {c: np.empty(resamples) for c in CHOICES}
    out_of_bag = {c: np.empty(resamples) for c in CHOICES}
    for b in range(resamples):
        pick = rng.integers(w, size=w)
        counts = np.bincount(pick, minlength=w)
        cells = resampler.cells(counts)
        for c in CHOICES:
            penalty = penalty_at(scores, own, cells[c])
            boot[c][b] = np.nanmean(penalty[pick])
            left_out = penalty[counts == 0]  # none, rarely, with very few workers
            out_of_bag[c][b] = np.nanmean(left_out) if left_out.size else np.nan
    held_out = {c: np.empty(splits) for c in CHOICES}
    in_half = {c: np.empty(splits) for c in CHOICES}
    for s in range(splits):
        order = rng.permutation(w)
        train, test = order[: w // 2], order[w // 2:]
        cells = resampler.cells(np.bincount(train, minlength=w))
        own_cells = resampler.cells(np.bincount(test, minlength=w))
        for c in CHOICES:
            held_out[c][s] = np.nanmean(penalty_at(scores, own, cells[c])[test])
            in_half[c][s] = np.nanmean(penalty_at(scores, own, own_cells[c])[test])
    rows = []
    for c in CHOICES:
        penalty = penalty_at(scores, own, chosen[c])
        rows.append({
            "choice": c, "n": w, "in_sample_mean_penalty": float(np.nanmean(penalty)),
            "rechosen_mean_penalty": float(boot[c].mean()),
            "rechosen_ci_low": float(np.quantile(boot[c], 0.025)),
            "rechosen_ci_high": float(np.quantile(boot[c], 0.975)),
            "out_of_bag_mean_penalty": float(np.nanmean(out_of_bag[c])),
            "out_of_bag_ci_low": float(np.nanquantile(out_of_bag[c], 0.025)),
            "out_of_bag_ci_high": float(np.nanquantile(out_of_bag[c], 0.975)),
            "split_half_held_out": float(held_out[c].mean()),
            "split_half_held_out_q025": float(np.quantile(held_out[c], 0.025)),
            "split_half_held_out_q975": float(np.quantile(held_out[c], 0.975)),
            "split_half_in_sample": float(in_half[c].mean()),
            "optimism": float(held_out[c].mean() - in_half[c].mean()),
            "resamples": resamples, "splits": splits})
    return rows
