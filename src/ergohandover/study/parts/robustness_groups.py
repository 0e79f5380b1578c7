"""The robustness part's groups of bodies and models: the sensitivity part's model variants, the
population part's workers and the participants — each scored at the default worker's
recommendations (regret), each with its own nominal and robust location."""

from __future__ import annotations

import numpy as np
import pandas as pd
from tqdm import tqdm

from ...landscape.stats import optimum
from ...robustness.posture_error import SCORES, ErrorModel, monte_carlo
from ...robustness.search import postures_at
from ...twin.evaluate import Evaluator, evaluate
from ..config import StudyConfig
from ..engines import Engine
from ..participants import DEFAULT_WORKER
from ..population import CHOICES, one_size_cells, penalty_regression
from ..robustness import (
    bootstrap_mean,
    own_minimum,
    practice_location,
    regret_rows,
    robust_pair,
    without_optimism,
)
from ..sensitivity import variants
from ..workforce import bodies
from .population import workforce_of
from .shared import default_landscape, grid_of, landscapes

POPULATION_SDS = (0.0, 2.0, 5.0)
"""The posture-error SDs of the one-size against personal comparison [deg]."""


def paired(name: str, first: np.ndarray, second: np.ndarray, rng: np.random.Generator,
           resamples: int, **extra) -> dict:
    """A comparison over variants or workers: the mean of ``first - second`` with a bootstrap
    interval, the shares lower and not higher, the worst case; survives when the interval is
    below 0."""
    diff = np.asarray(first, float) - np.asarray(second, float)
    mean, low, high = bootstrap_mean(diff, rng, resamples)
    taken = diff[~np.isnan(diff)]
    return {"comparison": name, **extra, "n": int(taken.size), "difference": mean,
            "ci_low": low, "ci_high": high, "p_lower": float((taken < 0).mean()),
            "p_not_higher": float((taken <= 0).mean()), "worst": float(taken.max()),
            "survives": bool(high < 0)}


def variant_tables(config: StudyConfig, engine: Engine, named: pd.DataFrame,
                   recommendations: pd.DataFrame, rng: np.random.Generator) -> dict:
    """Every sensitivity variant at the default's recommendations (regret) and at the baselines'
    locations: does the recommendation still beat them when the model is wrong?"""
    base = config.evaluator()
    chosen = variants(base)
    evaluators = [v.evaluator(base) for v in chosen]
    grid = grid_of(base, config.landscape.boundary, config.sensitivity.step)
    print(f"  {len(chosen)} model variants at the recommendations")
    found = landscapes(engine, evaluators, grid)
    points = named[["x", "y", "z"]].to_numpy(float)
    regret, scored = [], []
    for variant, evaluator, landscape in tqdm(zip(chosen, evaluators, found, strict=True),
                                              total=len(chosen), unit="variant",
                                              desc="variants at the recommendations"):
        at = evaluate(points, evaluator)
        own = {s: own_minimum(landscape, s) for s in SCORES}
        mine = at[named["location"].isin(recommendations["location"]).to_numpy()]
        regret += regret_rows("sensitivity", variant.name, mine.reset_index(drop=True), own,
                              recommendations, SCORES)
        scored.append(at)
    compared = []
    others = [b for b in named["location"] if b.startswith(("shortest", "practice"))]
    index = {name: i for i, name in enumerate(named["location"])}
    for a in recommendations["location"]:
        for b in others:
            for score in SCORES:
                # A variant that cannot take the box at a location has no score there (NA):
                # that pair is left out of the comparison.
                values = np.array([[t[score].iloc[index[a]], t[score].iloc[index[b]]]
                                   for t in scored], dtype=object)
                values = np.where(pd.isna(values), np.nan, values).astype(float)
                compared.append(paired(f"{a} vs {b}", values[:, 0], values[:, 1], rng,
                                       config.robustness.resamples, a=a, b=b, score=score,
                                       perturbation="model variants"))
    return {"regret": pd.DataFrame(regret), "comparisons": pd.DataFrame(compared)}


def participant_locations(config: StudyConfig, engine: Engine, seed: int) -> pd.DataFrame:
    """Each participant's nominal and robust location (the default worker on the landscape
    part's grid, the others on the participants part's)."""
    rows = []
    for name in tqdm(dict.fromkeys([DEFAULT_WORKER, *config.participants.workers]),
                     desc="participants' robust optima", unit="worker"):
        evaluator = config.evaluator(name)
        if name == DEFAULT_WORKER:
            landscape, stride = default_landscape(config, engine), config.robustness.stride
        else:
            grid = grid_of(evaluator, config.landscape.boundary, config.participants.step)
            landscape, stride = landscapes(engine, [evaluator], grid)[0], 1
        rows.append({"source": "participants", "worker": name,
                     **robust_pair(landscape, evaluator, config.robustness, stride, seed)})
    return pd.DataFrame(rows)


def population_tables(config: StudyConfig, engine: Engine, recommendations: pd.DataFrame,
                      rng: np.random.Generator, seed: int) -> dict:
    """The population's workers: regret at the recommendations, the one-size choices without
    optimism, the penalty on stature and sex, one-size against personal under posture error,
    and each worker's robust location."""
    pop, part = config.population, config.robustness
    table = workforce_of(pop)
    evaluators = [Evaluator(b, config.task()) for b in bodies(table)]
    grid = grid_of(evaluators[-1], pop.boundary, pop.step)
    print(f"  {len(evaluators)} workers of the population")
    found = landscapes(engine, evaluators, grid)
    sampled = np.flatnonzero(table["reference"].to_numpy() == 0)
    reference = found[-1]
    points = grid.points()
    one_size, regression, chosen = [], [], {}
    for objective in SCORES:
        scores = np.stack([found[w].arrays[objective] for w in sampled]).astype(float)
        scores[scores < 0] = np.nan
        own = np.array([own_minimum(found[w], objective) for w in sampled])
        ref_cell = reference.grid.nearest_cell(optimum(reference, objective)[1])
        chosen[objective] = one_size_cells(scores, points, ref_cell)
        one_size += [{"objective": objective, **row} for row in without_optimism(
            scores, own, points, ref_cell, rng, part.resamples, part.splits)]
        for choice in CHOICES:
            penalty = scores[:, chosen[objective][choice]] - own
            regression += [{"objective": objective, "choice": choice, **row}
                           for row in penalty_regression(penalty, {
                               "stature_m": table["stature_m"].to_numpy(float)[sampled],
                               "male": (table["sex"].to_numpy()[sampled] == "male")
                               .astype(float)})]
    regret, personal, expected = [], [], []
    recs = recommendations[["x", "y", "z"]].to_numpy(float)
    for w in tqdm(sampled, desc="workers: regret, robust optima", unit="worker"):
        evaluator, landscape = evaluators[w], found[w]
        worker = str(table["worker"].iloc[w])
        own = {s: own_minimum(landscape, s) for s in SCORES}
        regret += regret_rows("population", worker, evaluate(recs, evaluator), own,
                              recommendations, SCORES)
        pair = robust_pair(landscape, evaluator, part, part.worker_stride, seed)
        personal.append({"source": "population", "worker": worker, **pair})
        locations = np.stack([
            [pair["nominal_x"], pair["nominal_y"], pair["nominal_z"]],
            *(points[chosen["paper_postural"][c]] for c in CHOICES),
            practice_location(evaluator, evaluator.body.elbow_height_m)])
        posture, feasible = postures_at(locations, evaluator)
        row = []
        for sd in POPULATION_SDS:
            mc = monte_carlo(posture, ErrorModel(sd, part.structure), part.worker_draws, rng,
                             scores=("paper_postural",))
            row.append(np.where(feasible, mc.mean["paper_postural"], np.nan))
        expected.append(row)
    expected = np.array(expected)  # (workers, SDs, locations)
    compared = []
    names = ["personal optimum", *(f"one-size {c}" for c in CHOICES), "practice"]
    for k, sd in enumerate(POPULATION_SDS):
        for j, b in enumerate(names[1:], start=1):
            compared.append(paired(f"personal optimum vs {b}", expected[:, k, 0],
                                   expected[:, k, j], rng, part.resamples,
                                   a="personal optimum", b=b, score="paper_postural",
                                   perturbation="posture error, workers", angle_sd_deg=sd))
    return {"regret": pd.DataFrame(regret), "personal": pd.DataFrame(personal),
            "one_size": pd.DataFrame(one_size), "regression": pd.DataFrame(regression),
            "comparisons": pd.DataFrame(compared)}
