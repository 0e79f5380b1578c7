"""Study part `robustness`: does the recommendation survive being measured?

The study's headline locations (the landscape's nominal optimum, the robust optimum under
posture error, the location of largest margin, the learner's location, each start's shortest-
distance location, the practice location and the population's one-size locations) are scored
under posture-measurement error (Monte Carlo, every angle with Gaussian error of each SD), under
the robot's placement error (the landscape's cells within a ball, the twin's beyond it) and
under the model variants of the sensitivity part and the workers of the population part
(regret); the population's one-size locations are re-chosen inside the bootstrap and across
split halves; the robot carries the box to the practice location from the paper's starts.

Writes results/robustness/:
  locations.csv      location x score x angle SD: nominal, mean, P(score <= nominal), q05, q95
  flips.csv          location x angle SD x item score: how often the item differs from nominal
  margins.csv        location x angle x score: the smallest move of that angle that changes it
  placement.csv      location x radius x score: the score expected when the box lands off target
  comparisons.csv    every headline comparison under posture error, model variants and workers
  regret.csv, regret_summary.csv   the recommendation's regret per variant and worker
  one_size.csv, penalty_regression.csv   the one-size choices without optimism; penalty on
                     stature and sex together
  personal.csv       each participant's and worker's nominal and robust location, and the
                     robust location among cells at the error-free optimum (the trade)
  practice_carries.csv   the robot's carry of the box to the practice location from each of the
                     paper's starts (the baselines' columns)
  measured_locations.csv, measured_flips.csv, measured_comparisons.csv   the same under the
                     error measured for an IMU system (per-joint bias and SD, correlated within a
                     segment and between sides; robustness.measured_error) and its variants
  measured_error.csv the measured model's bias and SD per angle and where each comes from
  expected_landscape.csv   the screened expected paper score in the plane x = 0 (for the figure)
  manifest.json
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

from ...ergonomics import Posture, ScoringSettings
from ...io.atomic import atomic_write_csv
from ...robustness.margins import margin_table
from ...robustness.measured_error import MEASURED_ERROR, MEASURED_VARIANTS
from ...robustness.posture_error import SCORES, ErrorModel, monte_carlo
from ...robustness.search import largest_margin, placement, postures_at
from ...scene.robot import RobotSpec
from ...twin.evaluate import Evaluator
from ..baselines.comparison import PAPER_STARTS, compare
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import default_landscape
from .analysis import (
    PRACTICE,
    ROBUST_SCORE,
    difference,
    practice_location,
    regret_summary,
    robust_recommendation,
    search_seed,
)
from .config import RobustnessConfig
from .groups import participant_locations, population_tables, variant_tables


def headline_locations(results: Path, nominal: np.ndarray, robust: np.ndarray,
                       margin: np.ndarray, practice: np.ndarray) -> pd.DataFrame:
    """Every headline location of the default worker: name, x, y, z."""
    rows = [("nominal optimum", *nominal), ("robust optimum", *robust),
            ("largest margin", *margin)]
    base = pd.read_csv(results / "baselines" / "baselines.csv")
    learned = base[base["method"] == "optimised"].iloc[0]
    rows.append(("learned", learned["x"], learned["y"], learned["z"]))
    shortest = base[base["method"] == "shortest_distance"].reset_index(drop=True)
    rows += [(f"shortest distance, start {k + 1}", r["x"], r["y"], r["z"])
             for k, r in shortest.iterrows()]
    rows.append(("practice", *practice))
    one_size = pd.read_csv(results / "population" / "one_size.csv")
    for _, r in one_size[one_size["objective"] == ROBUST_SCORE].iterrows():
        if r["choice"] != "reference":  # the reference's optimum is the nominal optimum's cell
            rows.append((f"one-size {r['choice']}", r["x"], r["y"], r["z"]))
    return pd.DataFrame(rows, columns=["location", "x", "y", "z"])


def named_postures(named: pd.DataFrame, evaluator: Evaluator) -> Posture:
    """The twin's posture at every headline location (each one it must be able to take)."""
    posture, feasible = postures_at(named[["x", "y", "z"]].to_numpy(float), evaluator)
    if not feasible.all():
        bad = named["location"][~feasible].tolist()
        raise RuntimeError(f"the twin cannot take the box at {bad}")
    return posture


def posture_tables(named: pd.DataFrame, posture: Posture, settings: ScoringSettings,
                   part: RobustnessConfig,
                   models: list[tuple[dict, object, np.random.Generator]]) -> dict[
                       str, pd.DataFrame]:
    """The headline locations' postures under posture error: their score distributions and
    item flips, and the comparisons between them, for each error model (``models``: the
    columns that label it in the tables, the model, its generator); ``settings``: the
    twin's scoring settings."""
    tables, flips, compared = [], [], []
    pairs = [(a, b) for a in ("nominal optimum", "robust optimum")
             for b in named["location"] if b.startswith(("shortest", "practice"))]
    index = {name: i for i, name in enumerate(named["location"])}
    for labels, model, rng in tqdm(models, desc="posture error", unit="model"):
        mc = monte_carlo(posture, model, part.draws, rng, keep=True, settings=settings)
        table = mc.table(named["location"]).merge(named, on="location")
        tables.append(table.assign(**labels))
        for item, share in mc.flips.items():
            flips.append(pd.DataFrame({"location": named["location"], **labels,
                                       "item": item, "p_flip": share}))
        for a, b in pairs:
            for score in SCORES:
                compared.append({"comparison": f"{a} vs {b}", "a": a, "b": b, "score": score,
                                 "perturbation": "posture error", **labels,
                                 "n": part.draws, **difference(mc.values[score][index[a]],
                                                               mc.values[score][index[b]])})
    columns = ["location", "x", "y", "z", "score", *models[0][0], "nominal", "mean", "mean_se",
               "p_nominal_or_better", "q05", "q95", "draws"]
    return {"locations": pd.concat(tables, ignore_index=True)[columns],
            "flips": pd.concat(flips, ignore_index=True),
            "comparisons": pd.DataFrame(compared)}


def placement_table(named: pd.DataFrame, landscape, evaluator, radii_cm) -> pd.DataFrame:
    """Each headline location's expected score when the robot delivers the box uniformly
    within a ball of each radius (the landscape's cells; the twin's beyond the grid)."""
    rows = []
    for _, loc in named.iterrows():
        for radius in radii_cm:
            for score in SCORES:
                rows.append({"location": loc["location"], "radius_cm": radius, "score": score,
                             **placement(landscape, loc[["x", "y", "z"]].to_numpy(float),
                                         radius / 100, score, evaluator)})
    return pd.DataFrame(rows)


def practice_carries(config: StudyConfig, engine: Engine, landscape,
                     practice: np.ndarray) -> pd.DataFrame:
    """The robot's carry of the box to the practice location from each of the paper's starts,
    planned as the baselines' carries are (their seed and robot)."""
    print("  the robot's carries to the practice location")
    table = compare(PAPER_STARTS, landscape, config.evaluator(), RobotSpec(),
                    seed=config.baselines.seed, methods=("optimised",), location=practice,
                    executor=engine.executor(isolated=True)).table
    # compare() names the given location "optimised" and puts the paper's optimised numbers
    # beside it: here it is the practice location, which the paper has no number for.
    return table.assign(method="practice").drop(columns="paper_postural_paper")


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.robustness

    def work(folder: Path) -> dict:
        # A spawned child does not depend on how many are spawned: the sixth leaves the
        # first five streams, and so their tables, as they are.
        seeds = np.random.SeedSequence(part.seed).spawn(6)
        seed = search_seed(part)  # seeds[0]'s
        evaluator = config.evaluator()
        landscape = default_landscape(config, engine)
        print(f"  the robust optimum (expected {ROBUST_SCORE} at {part.robust_sd:g} deg) and "
              "the location of largest margin")
        nominal, robust = robust_recommendation(landscape, evaluator, part, seed, part.draws,
                                                part.stride, part.keep, part.radius,
                                                engine.workers)
        margin = largest_margin(landscape, evaluator, ROBUST_SCORE, part.stride,
                                workers=engine.workers)
        practice = practice_location(evaluator, evaluator.body.elbow_height_m)
        named = headline_locations(results, nominal, robust.location, margin.location,
                                   practice)
        posture = named_postures(named, evaluator)
        tables = posture_tables(named, posture, evaluator.scoring, part, [
            ({"angle_sd_deg": sd, "structure": part.structure},
             ErrorModel(sd, part.structure), np.random.default_rng(s))
            for sd, s in zip(part.angle_sds, seeds[1].spawn(len(part.angle_sds)), strict=True)])
        models = (MEASURED_ERROR, *MEASURED_VARIANTS.values())
        measured = posture_tables(named, posture, evaluator.scoring, part, [
            ({"error_model": model.name}, model, np.random.default_rng(s))
            for model, s in zip(models, seeds[5].spawn(len(models)), strict=True)])
        tables |= {f"measured_{name}": table for name, table in measured.items()}
        tables["margins"] = margin_table(posture, named["location"],
                                         settings=evaluator.scoring).merge(named, on="location")
        tables["measured_error"] = MEASURED_ERROR.table().assign(
            within_segment=MEASURED_ERROR.within_segment,
            between_sides=MEASURED_ERROR.between_sides, source=MEASURED_ERROR.source)
        tables["placement"] = placement_table(named, landscape, evaluator,
                                              part.placement_radii_cm)
        tables["practice_carries"] = practice_carries(config, engine, landscape, practice)
        recommendations = named[named["location"].isin(("nominal optimum", "robust optimum"))]
        variants = variant_tables(config, engine, named, recommendations,
                                  np.random.default_rng(seeds[2]))
        population = population_tables(config, engine, recommendations,
                                       np.random.default_rng(seeds[3]), seed)
        personal = participant_locations(config, engine, seed)
        tables["comparisons"] = pd.concat([tables["comparisons"], variants["comparisons"],
                                           population["comparisons"]], ignore_index=True)
        tables["regret"] = pd.concat([variants["regret"], population["regret"]],
                                     ignore_index=True)
        tables["regret_summary"] = regret_summary(tables["regret"],
                                                  np.random.default_rng(seeds[4]),
                                                  part.resamples)
        tables["one_size"] = population["one_size"]
        tables["penalty_regression"] = population["regression"]
        tables["personal"] = pd.concat([personal, population["personal"]], ignore_index=True)
        screened = robust.screened
        middle = screened["x"].iloc[int(np.argmin(screened["x"].abs().to_numpy()))]
        plane = screened["x"] == middle  # the screened plane nearest the body's midline
        tables["expected_landscape"] = screened[plane].drop(columns="cell").rename(
            columns={"value": "expected"})
        for name, frame in tables.items():
            atomic_write_csv(frame, folder / f"{name}.csv")
        return {"robust_optimum": [round(float(v), 6) for v in robust.location],
                "robust_expected": robust.value, "largest_margin_deg": margin.value,
                "practice": PRACTICE, "locations": len(named)}

    return run_part("robustness", results / "robustness", config.part_inputs("robustness"),
                    work, seeds={"robustness": part.seed}, force=force, engine=engine)
