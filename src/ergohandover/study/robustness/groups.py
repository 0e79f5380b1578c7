"""The robustness part's groups of bodies and models: the sensitivity part's model variants, the
population part's workers and the participants — each scored at the default worker's
recommendations (regret), each with its own nominal and robust location."""

from __future__ import annotations

import numpy as np
import pandas as pd
from tqdm import tqdm

from ...landscape.stats import minimum, optimum
from ...landscape.store import landscape_of
from ...robustness.posture_error import SCORES, ErrorModel, monte_carlo
from ...robustness.search import postures_at
from ...twin.evaluate import Evaluator, evaluate
from ..choices import DEFAULT_WORKER
from ..config import StudyConfig
from ..engines import Engine
from ..population.one_size import CHOICES, one_size_cells, penalty_regression
from ..sensitivity.variants import variants
from ..shared import grid_of, landscape, landscapes
from ..workforce import bodies
from .analysis import (
    bootstrap_mean,
    practice_location,
    regret_rows,
    robust_pair,
    without_optimism,
)

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
    with engine.executor() as executor:
        scored = list(tqdm(executor.map(_evaluate_job, [(points, e) for e in evaluators]),
                           total=len(chosen), unit="variant",
                           desc="variants at the recommendations"))
    regret = []
    for variant, found_here, at in zip(chosen, found, scored, strict=True):
        own = {s: minimum(found_here, s) for s in SCORES}
        mine = at[named["location"].isin(recommendations["location"]).to_numpy()]
        regret += regret_rows("sensitivity", variant.name, mine.reset_index(drop=True), own,
                              recommendations, SCORES)
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


def _evaluate_job(job: tuple) -> pd.DataFrame:
    """The twin of one variant at the headline locations."""
    points, evaluator = job
    return evaluate(points, evaluator)


def participant_locations(config: StudyConfig, engine: Engine, seed: int) -> pd.DataFrame:
    """Each participant's nominal and robust location (the default worker on the landscape
    part's grid, the others on the participants part's), a job per worker on the engine."""
    names = list(dict.fromkeys([DEFAULT_WORKER, *config.participants.workers]))
    jobs = []
    for name in names:
        evaluator = config.evaluator(name)
        if name == DEFAULT_WORKER:
            grid = grid_of(evaluator, config.landscape.boundary, config.landscape.step)
            landscape(engine, evaluator, grid)  # in the cache before the jobs read it
            jobs.append((evaluator, grid, config.robustness, config.robustness.stride, seed))
        else:
            grid = grid_of(evaluator, config.landscape.boundary, config.participants.step)
            landscapes(engine, [evaluator], grid)
            jobs.append((evaluator, grid, config.robustness, 1, seed))
    with engine.executor() as executor:
        pairs = list(tqdm(executor.map(_participant_pair, jobs), total=len(jobs),
                          desc="participants' robust optima", unit="worker"))
    return pd.DataFrame([{"source": "participants", "worker": name, **pair}
                         for name, pair in zip(names, pairs, strict=True)])


def _participant_pair(job: tuple) -> dict:
    """One participant's :func:`robust_pair`, its landscape read from the cache (the 3 mm
    landscape is about 160 MB: a job names it rather than carrying it; where the cache lacks it,
    as on another machine of a cluster, the job sweeps it there)."""
    evaluator, grid, part, stride, seed = job
    return robust_pair(landscape_of(evaluator, grid, progress=False), evaluator, part, stride,
                       seed)


def _worker_job(job: tuple) -> tuple:
    """One population worker's twin work: its scores at the recommendations, its nominal and
    robust pair, and its postures at its personal optimum, the one-size cells and its practice
    location (the Monte Carlo draws stay with the caller, in worker order)."""
    evaluator, found, recs, part, seed, one_size_points = job
    at = evaluate(recs, evaluator)
    pair = robust_pair(found, evaluator, part, part.worker_stride, seed)
    locations = np.stack([[pair["nominal_x"], pair["nominal_y"], pair["nominal_z"]],
                          *one_size_points,
                          practice_location(evaluator, evaluator.body.elbow_height_m)])
    posture, feasible = postures_at(locations, evaluator)
    return at, pair, posture, feasible


def population_tables(config: StudyConfig, engine: Engine, recommendations: pd.DataFrame,
                      rng: np.random.Generator, seed: int) -> dict:
    """The population's workers: regret at the recommendations, the one-size choices without
    optimism, the penalty on stature and sex, one-size against personal under posture error,
    and each worker's robust location."""
    pop, part = config.population, config.robustness
    table = pop.workers()
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
        own = np.array([minimum(found[w], objective) for w in sampled])
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
    one_size_points = [points[chosen["paper_postural"][c]] for c in CHOICES]
    jobs = [(evaluators[w], found[w], recs, part, seed, one_size_points) for w in sampled]
    with engine.executor() as executor:
        done = list(tqdm(executor.map(_worker_job, jobs), total=len(jobs),
                         desc="workers: regret, robust optima", unit="worker"))
    for w, (at, pair, posture, feasible) in zip(sampled, done, strict=True):
        worker = str(table["worker"].iloc[w])
        own = {s: minimum(found[w], s) for s in SCORES}
        regret += regret_rows("population", worker, at, own, recommendations, SCORES)
        personal.append({"source": "population", "worker": worker, **pair})
        row = []
        for sd in POPULATION_SDS:
            mc = monte_carlo(posture, ErrorModel(sd, part.structure), part.worker_draws, rng,
                             scores=("paper_postural",), settings=evaluators[w].scoring)
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
