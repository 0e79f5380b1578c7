"""Who pays for a one-size handover location: the population study's post hoc tests
(planned after the straight-line analysis was seen).

The plan (docs/population.md#the-analysis-plan; the same for every score and location):
- the response is a worker's penalty at a one-size location (score there less their own
  optimum), one model per score and one-size location;
- stature enters as a restricted cubic spline (:data:`KNOT_QUANTILES`: Harrell's default knots
  for four, linear beyond the outer ones), because a penalty is often lowest for workers near
  the size the location was chosen for and rises on both sides, which a straight line fits as
  no effect or as a spurious one; elbow height / stature and arm length / stature are covariates
  (proportions beyond stature);
- standard errors are heteroskedasticity-consistent (HC3; Long & Ervin 2000, The American
  Statistician 54:217-224), because a penalty's spread differs between the sizes it serves and
  those it does not; tests use t (or F) with n - terms degrees of freedom;
- two questions per model, the family of "who pays" tests: does sex matter beyond body size
  (the ``male`` coefficient, a Wald t-test) and does stature matter (the spline's terms
  together, a Wald F-test); Holm's step-down adjustment over every test of the family (both
  questions, every score, every one-size location whose penalty varies at all).
The straight-line, ordinary-least-squares fit the population part reported before the plan
(``proportions.csv``) is kept beside it, as are the plan's two departures from it taken one at a
time, so that a reader sees which choice moves a p-value.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...search.statistics import holm

KNOT_QUANTILES = (0.05, 0.35, 0.65, 0.95)
"""Where the spline's knots sit among the workers' statures (Harrell FE (2015), Regression
Modeling Strategies, 2nd ed., Springer, section 2.4.6: the quantiles for four knots)."""
MODELS = {"straight line, OLS errors": (False, "nonrobust"),
          "straight line, HC3 errors": (False, "HC3"),
          "spline, OLS errors": (True, "nonrobust"),
          "spline, HC3 errors": (True, "HC3")}
"""Each model's name -> (stature as a spline rather than a straight line, the standard errors
as statsmodels' ``cov_type``); the last is the plan's."""
PLANNED = "spline, HC3 errors"
QUESTIONS = ("sex beyond body size", "stature")
COLUMNS = ("objective", "choice", "question", "model", "estimate", "se", "ci_low", "ci_high",
           "statistic", "df", "p", "n")


def restricted_cubic_spline(x: np.ndarray, knots: np.ndarray) -> np.ndarray:
    """(n, k - 1) columns of a restricted cubic spline in ``x`` with ``k`` knots: ``x`` itself
    and k - 2 cubic terms that are linear beyond the outer knots (Harrell's form, each term
    divided by the squared span of the knots so that the columns have comparable scales)."""
    t = np.asarray(knots, dtype=float)
    cube = lambda v: np.clip(v, 0.0, None) ** 3  # noqa: E731
    last, before = t[-1], t[-2]
    columns = [x]
    for tj in t[:-2]:
        columns.append((cube(x - tj) - cube(x - before) * (last - tj) / (last - before)
                        + cube(x - last) * (before - tj) / (last - before)) / (last - t[0]) ** 2)
    return np.column_stack(columns)


def sex_and_stature_tests(penalty: np.ndarray, stature: np.ndarray, male: np.ndarray,
          proportions: dict[str, np.ndarray]) -> list[dict]:
    """Both questions of the family under every model of :data:`MODELS` for one score and
    one-size location: the sex coefficient (points of penalty, man less woman) with its 95 %
    interval and p, and the stature terms' joint F and p; workers without a penalty left out.
    No rows when the penalty is the same for everyone (nothing to explain) or when the workers
    are too few for a model (fewer than 2 residual degrees of freedom)."""
    import statsmodels.api as sm

    taken = ~np.isnan(penalty)
    y = penalty[taken]
    if y.size == 0 or np.ptp(y) == 0:
        return []
    knots = np.quantile(stature[taken], KNOT_QUANTILES)
    rows = []
    for model, (spline, errors) in MODELS.items():
        size = restricted_cubic_spline(stature[taken], knots) if spline else \
            stature[taken][:, None]
        x = np.column_stack([np.ones(y.size), size, male[taken],
                             *(v[taken] for v in proportions.values())])
        if y.size - x.shape[1] < 2:
            continue
        fit = sm.OLS(y, x).fit(cov_type=errors, use_t=True)
        sex = 1 + size.shape[1]
        low, high = fit.conf_int(0.05)[sex]
        rows.append({"question": QUESTIONS[0], "model": model, "estimate": fit.params[sex],
                     "se": fit.bse[sex], "ci_low": low, "ci_high": high,
                     "statistic": fit.tvalues[sex], "df": fit.df_resid,
                     "p": fit.pvalues[sex], "n": int(y.size)})
        joint = np.zeros((size.shape[1], x.shape[1]))
        joint[:, 1:sex] = np.eye(size.shape[1])
        f = fit.f_test(joint)
        rows.append({"question": QUESTIONS[1], "model": model, "estimate": np.nan,
                     "se": np.nan, "ci_low": np.nan, "ci_high": np.nan,
                     "statistic": float(np.squeeze(f.fvalue)), "df": fit.df_resid,
                     "p": float(f.pvalue), "n": int(y.size)})
    return rows


def with_holm(table: pd.DataFrame) -> pd.DataFrame:
    """The table with ``p_holm``: Holm's adjustment over the planned model's rows (the family);
    empty for the other models, which are not the plan's tests."""
    if table.empty:
        return pd.DataFrame(columns=[*COLUMNS, "p_holm", "family"])
    planned = table["model"] == PLANNED
    adjusted = np.full(len(table), np.nan)
    adjusted[planned.to_numpy()] = holm(table.loc[planned, "p"].to_numpy(float))
    return table.assign(p_holm=adjusted, family=int(planned.sum()))
