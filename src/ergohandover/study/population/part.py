"""Study part `population`: one handover location for everyone, or one per worker?

A workforce is drawn from the body model fitted to the ANSUR II survey (size, seed and sex mix
in the configuration): whole bodies whose proportions vary as people's do. Every worker, and the
reference worker (the 50th-percentile man), gets a landscape on one shared grid, swept through
the study's engine: the local process pool or Ray. Landscapes stream into the landscape cache
as they finish, so a killed run resumes without redoing finished workers.

Writes results/population/:
  workers.csv     each worker's body (every measurement), landmarks and proportions, own
                  optimum per objective (paper score, REBA, RULA: score, location, how many
                  cells share it, the median height of those cells, the optimum's distance
                  from the height-against-stature line)
                  and whether the default robot can hold the box at the paper-score optimum
  penalties.csv   each worker at each one-size location (the reference's optimum, the lowest
                  mean, the lowest 95th percentile): the three scores there and the penalty
  one_size.csv    per objective and choice: the location, the workforce's mean and 95th-percentile
                  score, mean penalty (bootstrap 95 % interval), share penalised (Wilson 95 %)
  groups.csv      the same by sex and stature band: who pays
  height_fit.csv  the optimum's height against stature and elbow height (line, R², residuals,
                  slope interval) and its offset from elbow height
  working_heights.csv  how many workers' optima (paper score) lie in each published range of
                  standing working height below the elbow (the validation's sources)
  proportions.csv  penalty at each one-size location against stature, sex and proportions
                  (elbow height / stature, arm length / stature): least squares, each term's
                  coefficient, 95 % interval and p-value (the fit reported before the plan)
  who_pays_tests.csv  the post hoc "who pays" tests (docs/population.md#the-analysis-plan):
                  per score and distinct one-size location, sex beyond body size and stature,
                  under the plan's model (stature as a spline, HC3 errors) and the three it
                  departs from; Holm-adjusted p over the plan's family
  fixed_ratio_twin.csv  the reference worker's optimum per objective sized by the survey's body
                  model and by the fixed-ratio twin's fixed ratios of stature
  manifest.json
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

from ...executor import LocalExecutor
from ...io.atomic import atomic_write_csv
from ...landscape.grid import Grid
from ...landscape.stats import optimum
from ...landscape.store import landscapes_of
from ...scene.robot import RobotSpec
from ...twin.evaluate import Evaluator
from ..baselines.reachability import holds
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import grid_of, landscape, where
from ..workforce import bodies
from .analysis import OBJECTIVES, analyse


def fixed_ratio_twin(grid: Grid, reference: Evaluator, engine: Engine) -> pd.DataFrame:
    """The reference worker's optimum per objective, sized by the survey's body model and by
    the fixed-ratio twin's fixed ratios of stature (Drillis & Contini), on the population's grid."""
    twins = {"ansur2": reference, "drillis-contini": dataclasses.replace(
        reference, body=dataclasses.replace(reference.body, proportions="drillis-contini"))}
    rows = []
    for name, evaluator in twins.items():
        found = landscape(engine, evaluator, grid)
        for objective in OBJECTIVES:
            cells, best = optimum(found, objective)
            rows.append({"proportions": name, "objective": objective,
                         "elbow_height_m": round(evaluator.body.elbow_height_m, 4),
                         "elbow_joint_height_m": round(evaluator.body.elbow_joint_height_m, 4),
                         "optimum": int(found.arrays[objective][cells[0]]),
                         **{a: round(float(best[k]), 6) for k, a in enumerate("xyz")},
                         "cells": len(cells),
                         "region_y": round(float(np.median(grid.coordinates(cells)[:, 1])), 6)})
    return pd.DataFrame(rows)


def sweep_scores(grid: Grid, evaluators: list[Evaluator],
                 engine: Engine) -> tuple[dict, pd.DataFrame, dict]:
    """Every worker's scores on the grid (int8, -1 infeasible), its own optimum per objective,
    and how the sweep went (reused and computed workers, engine, seconds)."""
    matrices = {o: np.empty((len(evaluators), grid.size), dtype=np.int8) for o in OBJECTIVES}
    optima: list[dict] = [{} for _ in evaluators]
    reused = 0
    start = time.perf_counter()
    for done in landscapes_of(evaluators, grid, **where(engine)):
        reused += done.reused
        for objective in OBJECTIVES:
            matrices[objective][done.index] = done.landscape.arrays[objective]
            cells, best = optimum(done.landscape, objective)
            points = grid.coordinates(cells)  # every cell at the optimum; best is one
            optima[done.index] |= {
                f"{objective}_opt": int(done.landscape.arrays[objective][cells[0]]),
                **{f"{objective}_{a}": round(float(best[k]), 6) for k, a in enumerate("xyz")},
                f"{objective}_cells": len(cells),
                f"{objective}_cell": int(cells[(points == best).all(axis=1)][0]),
                f"{objective}_region_y": round(float(np.median(points[:, 1])), 6)}
    sweep = {"workers_reused": reused, "workers_computed": len(evaluators) - reused,
             "sweep_seconds": round(time.perf_counter() - start, 1)}
    return matrices, pd.DataFrame(optima), sweep


def _robot_holds(job: tuple[Evaluator, np.ndarray]) -> tuple[int, str]:
    """Whether the default robot holds the box at one worker's location (one process)."""
    evaluator, location = job
    held = holds(location[None], evaluator, RobotSpec(), workers=1).iloc[0]
    return int(held["held"]), held["reason"]


def robot_serves(table: pd.DataFrame, evaluators: list[Evaluator], workers: int) -> pd.DataFrame:
    """Can the default robot hold the box at each worker's paper-score optimum? One job per
    worker on one pool (each job solves the twin there and the robot's lifts)."""
    locations = table[["paper_postural_x", "paper_postural_y", "paper_postural_z"]].to_numpy(
        dtype=float)
    with LocalExecutor(workers) as executor:
        held = list(tqdm(executor.map(_robot_holds, zip(evaluators, locations, strict=True)),
                         total=len(evaluators), desc="robot holds each optimum", unit="worker"))
    return pd.DataFrame(held, columns=["robot_held", "robot_reason"])


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.population

    def work(folder: Path) -> dict:
        table = part.workers()
        task = config.task()
        evaluators = [Evaluator(body, task) for body in bodies(table)]
        # One grid for everyone (a one-size location must be a point of every landscape):
        # the boundary as drawn for the reference worker.
        grid = grid_of(evaluators[-1], part.boundary, part.step)
        print(f"  {len(table) - 1} workers and {part.reference} on {grid.describe()} "
              f"({engine.name} engine)")
        matrices, optima, sweep = sweep_scores(grid, evaluators, engine)
        table = pd.concat([table, optima], axis=1)
        table = pd.concat([table, robot_serves(table, evaluators, engine.workers)], axis=1)
        tables = analyse(table, matrices, grid, part)
        tables["fixed_ratio_twin"] = fixed_ratio_twin(grid, evaluators[-1], engine)
        for name, frame in tables.items():
            atomic_write_csv(frame, folder / f"{name}.csv")
        return {"grid": grid.describe(), **sweep}

    return run_part("population", results / "population", config.part_inputs("population"),
                    work, seeds={"workforce": part.seed, "bootstrap": part.bootstrap_seed},
                    force=force, engine=engine)
