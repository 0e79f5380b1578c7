"""The stance part's arithmetic: the study's headline locations scored for a planted worker and
for one who may step toward the box, and whether the optimised location still beats the
shortest-distance one.

Definitions (the README and report use these words): the **headline comparison** is the
optimised location against each start's shortest-distance location, per score; optimised
**beats** shortest distance from a start when its score is lower (and **survives** posture
error when the 95 % Monte Carlo interval of the difference of expected scores lies below zero,
as in the robustness part).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...robustness.posture_error import SCORES, ErrorModel, monte_carlo
from ...robustness.search import postures_at
from ...twin.evaluate import Evaluator, evaluate
from ..robustness.analysis import difference


def scored(named: pd.DataFrame, evaluators: dict[str, Evaluator]) -> pd.DataFrame:
    """Each named location (columns ``worker, location, start, x, y, z``) scored by its
    worker's evaluator of each stance (``evaluators``: stance -> worker -> Evaluator): the rows
    of ``named`` once per stance, with ``stance, feasible, step_m`` and every score of
    :data:`SCORES` (empty where the worker cannot take the box)."""
    frames = []
    for stance, by_worker in evaluators.items():
        for worker, rows in named.groupby("worker", sort=False):
            table = evaluate(rows[["x", "y", "z"]].to_numpy(float), by_worker[worker])
            step = table["step_m"] if "step_m" in table else np.zeros(len(rows))
            frames.append(rows.assign(stance=stance, feasible=table["feasible"].to_numpy(),
                                      step_m=np.asarray(step, float),
                                      **{s: table[s].to_numpy() for s in SCORES}))
    return pd.concat(frames, ignore_index=True)


def headline(table: pd.DataFrame, optimised: str = "optimised") -> pd.DataFrame:
    """Per worker, stance, start and score: the optimised location's score less the
    shortest-distance one's, and whether it is lower (``beats``)."""
    rows = []
    for (worker, stance), group in table.groupby(["worker", "stance"], sort=False):
        best = group[group["location"] == optimised]
        if best.empty:
            continue
        for _, other in group[group["location"] == "shortest distance"].iterrows():
            for score in SCORES:
                a, b = best[score].iloc[0], other[score]
                diff = float(a) - float(b) if not (pd.isna(a) or pd.isna(b)) else np.nan
                rows.append({"worker": worker, "stance": stance, "start": other["start"],
                             "score": score, "optimised": a, "shortest_distance": b,
                             "difference": diff, "beats": bool(diff < 0)})
    return pd.DataFrame(rows)


def under_posture_error(named: pd.DataFrame, evaluators: dict[str, Evaluator],
                        angle_sds, draws: int, seed: int) -> pd.DataFrame:
    """The default worker's headline comparison under posture-measurement error, per stance:
    the difference of expected scores (optimised less each start's shortest distance) with its
    95 % Monte Carlo interval and whether it survives. The same errors for both stances (one
    generator per SD, from ``seed``), so that they differ by the stance alone."""
    rows = []
    points = named[["x", "y", "z"]].to_numpy(float)
    best = int(np.flatnonzero(named["location"].to_numpy() == "optimised")[0])
    others = np.flatnonzero(named["location"].to_numpy() == "shortest distance")
    seeds = np.random.SeedSequence(seed).spawn(len(angle_sds))
    for stance, evaluator in evaluators.items():
        posture, feasible = postures_at(points, evaluator)
        if not feasible.all():
            raise RuntimeError(f"the twin ({stance}) cannot take the box at "
                               f"{named['location'][~feasible].tolist()}")
        for sd, sd_seed in zip(angle_sds, seeds, strict=True):
            mc = monte_carlo(posture, ErrorModel(sd), draws, np.random.default_rng(sd_seed),
                             keep=True, settings=evaluator.scoring)
            for k in others:
                for score in SCORES:
                    rows.append({"stance": stance, "start": named["start"].iloc[k],
                                 "score": score, "angle_sd_deg": sd, "draws": draws,
                                 **difference(mc.values[score][best], mc.values[score][k])})
    return pd.DataFrame(rows)
