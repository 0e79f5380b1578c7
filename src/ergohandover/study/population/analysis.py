"""The population study's tables from its workers' scores: the one-size locations and every
worker's penalty there, who pays by sex and stature, how the optimum's height follows body size,
and how many optima lie in the published standing working heights (the arithmetic is
:mod:`.one_size`'s).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import stats

from ...landscape.grid import Grid
from .config import PopulationConfig
from .one_size import (
    CHOICES,
    line_fit,
    mean_interval,
    one_size_cells,
    penalty_regression,
    penalty_summary,
    who_pays,
    working_heights,
)
from .who_pays import sex_and_stature_tests, with_holm

OBJECTIVES = ("paper_postural", "reba", "rula")
"""The scores each worker's optimum and penalties are read for."""


def analyse(table: pd.DataFrame, matrices: dict, grid: Grid,
            part: PopulationConfig) -> dict[str, pd.DataFrame]:
    """The tables of the part: the workers (with their distance from the height fit), the
    one-size choices, penalties, who pays, the height fits and the working heights (sampled
    workers only; the reference worker contributes its optimum)."""
    rng = np.random.default_rng(part.bootstrap_seed)
    resamples = part.bootstrap
    points = grid.points()
    sampled = table["reference"].to_numpy() == 0
    reference = int(np.flatnonzero(~sampled)[0])
    workers = table[sampled].reset_index(drop=True)
    penalties, one_size, proportions, who_pays_tests = [], [], [], []
    predictors = {"stature_m": workers["stature_m"].to_numpy(float),
                  "male": (workers["sex"].to_numpy() == "male").astype(float),
                  "elbow_ratio": workers["elbow_ratio"].to_numpy(float),
                  "arm_ratio": workers["arm_ratio"].to_numpy(float)}
    proportion_terms = {k: predictors[k] for k in ("elbow_ratio", "arm_ratio")}
    for objective in OBJECTIVES:
        scores = matrices[objective][sampled].astype(float)
        scores[scores < 0] = np.nan
        own = workers[f"{objective}_opt"].to_numpy(dtype=float)
        cells = one_size_cells(scores, points, int(table[f"{objective}_cell"].iloc[reference]))
        for choice in CHOICES:
            cell = cells[choice]
            at = scores[:, cell]
            penalty = at - own
            x, y, z = np.round(points[cell], 6)
            for w, row in workers.iterrows():
                penalties.append({
                    "objective": objective, "choice": choice, "worker": row["worker"],
                    "sex": row["sex"], "stature_m": row["stature_m"], "x": x, "y": y, "z": z,
                    **{o: (matrices[o][w, cell] if matrices[o][w, cell] >= 0 else np.nan)
                       for o in OBJECTIVES},
                    "own_optimum": own[w], "penalty": penalty[w]})
            proportions += [{"objective": objective, "choice": choice, **row}
                            for row in penalty_regression(penalty, predictors)]
            if cell not in [cells[c] for c in CHOICES[:CHOICES.index(choice)]]:
                # A location chosen twice is one test, not two (the family counts locations).
                who_pays_tests += [
                    {"objective": objective, "choice": choice, **row}
                    for row in sex_and_stature_tests(penalty, predictors["stature_m"],
                                                     predictors["male"], proportion_terms)]
            taken = ~np.isnan(penalty)
            rho, p = stats.spearmanr(workers["stature_m"][taken], penalty[taken]) \
                if np.ptp(penalty[taken]) > 0 else (np.nan, np.nan)
            mean, low, high = mean_interval(at, rng, resamples)
            one_size.append({
                "objective": objective, "choice": choice, "x": x, "y": y, "z": z,
                "mean_score": mean, "mean_score_ci_low": low, "mean_score_ci_high": high,
                "p95_score": float(np.quantile(at[taken], 0.95, method="inverted_cdf")),
                "mean_own_optimum": own.mean(),
                **penalty_summary(penalty, rng, resamples),
                "spearman_stature": rho, "p_spearman": p})
    penalty_table = pd.DataFrame(penalties)
    fits = []
    for objective in OBJECTIVES:
        for response in ("y", "region_y"):
            height = workers[f"{objective}_{response}"].to_numpy(dtype=float)
            for predictor in ("stature_m", "elbow_height_m", "elbow_ratio"):
                fits.append({"objective": objective, "response": response,
                             "predictor": predictor,
                             **line_fit(workers[predictor].to_numpy(dtype=float), height, rng,
                                        resamples)})
            offset = height - workers["elbow_height_m"].to_numpy(dtype=float)
            mean, low, high = mean_interval(offset, rng, resamples)
            fits.append({"objective": objective, "response": response,
                         "predictor": "offset_from_elbow", "n": len(offset),
                         "mean_offset": mean, "mean_offset_ci_low": low,
                         "mean_offset_ci_high": high, "residual_sd": float(offset.std(ddof=1))})
    fits = pd.DataFrame(fits)
    # Each sampled worker's distance from the line of optimum height against stature.
    table = table.drop(columns=[f"{o}_cell" for o in OBJECTIVES])
    for objective in OBJECTIVES:
        line = fits[(fits["objective"] == objective) & (fits["response"] == "y")
                    & (fits["predictor"] == "stature_m")].iloc[0]
        table.loc[sampled, f"{objective}_y_residual"] = (
            workers[f"{objective}_y"] - line["intercept"] - line["slope"] * workers["stature_m"]
        ).to_numpy()
    below_elbow_cm = 100 * (workers["elbow_height_m"] - workers["paper_postural_y"])
    return {"workers": table, "penalties": penalty_table, "one_size": pd.DataFrame(one_size),
            "groups": who_pays(penalty_table, rng, resamples), "height_fit": fits,
            "working_heights": working_heights(below_elbow_cm.to_numpy(dtype=float)),
            "proportions": pd.DataFrame(proportions),
            "who_pays_tests": with_holm(pd.DataFrame(who_pays_tests))}
