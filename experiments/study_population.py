"""Study part `population`: one handover location for everyone, or one per worker?

A workforce is drawn from the ANSUR II survey's statistics (size, seed and sex mix in the
configuration); every worker, and the reference worker (the 50th-percentile man), gets a
landscape on one shared grid, swept through an executor: the local process pool (default) or
Ray (--engine ray; --address auto|HOST:PORT joins a running cluster). Landscapes stream into
the landscape cache as they finish, so a killed run resumes without redoing finished workers.

Usage: python experiments/study_population.py [--config ...] [--engine local|ray]
       [--address auto|HOST:PORT] [--size N] [--results DIR]

Writes results/population/:
  workers.csv     each worker's body, elbow height, own optimum per objective (paper score,
                  REBA, RULA: score, location, how many cells share it, the median height of
                  those cells, the optimum's distance from the height-against-stature line)
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
  manifest.json
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pandas as pd
import study_landscape
from scipy import stats

from ergohandover.executor import Executor
from ergohandover.io.atomic import atomic_write_csv
from ergohandover.landscape.grid import Grid, parse_boundary
from ergohandover.landscape.stats import optimum
from ergohandover.landscape.workforce_sweep import CHUNK_POINTS, sweep_workforce
from ergohandover.scene.robot import RobotSpec
from ergohandover.study.engines import ENGINES, make_executor
from ergohandover.study.parts import part_config, run_part, study_main, study_parser
from ergohandover.study.population import (
    CHOICES,
    line_fit,
    mean_interval,
    one_size_cells,
    penalty_summary,
    who_pays,
    working_heights,
)
from ergohandover.study.reachability import holds
from ergohandover.study.validation import elbow_height
from ergohandover.study.workforce import Workforce, bodies, sample_workforce
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator

ROOT = Path(__file__).resolve().parents[1]
OBJECTIVES = ("paper_postural", "reba", "rula")
SEEDS = {"workforce": "seed", "bootstrap": "bootstrap_seed"}


def workforce_of(part: dict) -> pd.DataFrame:
    """The sampled workers and, last, the reference worker, with their elbow heights."""
    table = sample_workforce(workforce_spec(part))
    table["reference"] = 0
    reference = BodySpec.from_percentile(part["reference"])
    table.loc[len(table)] = {"worker": part["reference"], "sex": reference.sex,
                             "stature_m": reference.stature_m, "mass_kg": reference.mass_kg,
                             "reference": 1}
    table["elbow_height_m"] = [round(elbow_height(b), 6) for b in bodies(table)]
    return table


def workforce_spec(part: dict) -> Workforce:
    return Workforce(part["size"], part["seed"], part["female_share"])


def sweep_scores(grid: Grid, evaluators: list[Evaluator], executor: Executor,
                 chunk: int) -> tuple[dict, pd.DataFrame, dict]:
    """Every worker's scores on the grid (int8, -1 infeasible), its own optimum per objective,
    and how the sweep went (reused and computed workers, CPUs, seconds)."""
    matrices = {o: np.empty((len(evaluators), grid.size), dtype=np.int8) for o in OBJECTIVES}
    optima: list[dict] = [{} for _ in evaluators]
    reused = 0
    start = time.perf_counter()
    with executor:
        cpus = getattr(executor, "cpus", getattr(executor, "workers", 1))
        for done in sweep_workforce(grid, evaluators, executor, chunk):
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
    sweep = {"engine": type(executor).__name__, "cpus": cpus, "workers_reused": reused,
             "workers_computed": len(evaluators) - reused,
             "sweep_seconds": round(time.perf_counter() - start, 1)}
    return matrices, pd.DataFrame(optima), sweep


def robot_serves(table: pd.DataFrame, evaluators: list[Evaluator], workers: int) -> pd.DataFrame:
    """Can the default robot hold the box at each worker's paper-score optimum?"""
    held = [holds(row[["paper_postural_x", "paper_postural_y", "paper_postural_z"]]
                  .to_numpy(dtype=float)[None], evaluator, RobotSpec(), workers).iloc[0]
            for (_, row), evaluator in zip(table.iterrows(), evaluators, strict=True)]
    return pd.DataFrame({"robot_held": [int(h["held"]) for h in held],
                         "robot_reason": [h["reason"] for h in held]})


def analyse(table: pd.DataFrame, matrices: dict, grid: Grid, part: dict) -> dict[str, pd.DataFrame]:
    """The tables of the part: the workers (with their distance from the height fit), the
    one-size choices, penalties, who pays, the height fits and the working heights (sampled
    workers only; the reference worker contributes its optimum)."""
    rng = np.random.default_rng(part["bootstrap_seed"])
    resamples = part["bootstrap"]
    points = grid.points()
    sampled = table["reference"].to_numpy() == 0
    reference = int(np.flatnonzero(~sampled)[0])
    workers = table[sampled].reset_index(drop=True)
    penalties, one_size = [], []
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
            for predictor in ("stature_m", "elbow_height_m"):
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
            "working_heights": working_heights(below_elbow_cm.to_numpy(dtype=float))}


def run(config: dict, results: Path, workers: int, force: bool = False, engine: str = "local",
        address: str | None = None) -> None:
    part = part_config(config, "population")
    # Every value is checked before anything is written or swept.
    workforce_spec(part)
    executor = make_executor(engine, workers, address)

    def work(folder: Path) -> dict:
        table = workforce_of(part)
        task = study_landscape.study_task(config)
        evaluators = [Evaluator(body, task) for body in bodies(table)]
        # One grid for everyone (a one-size location must be a point of every landscape):
        # the boundary as drawn for the reference worker.
        grid = Grid(parse_boundary(part["boundary"], evaluators[-1].body, task), part["step"])
        print(f"  {len(table) - 1} workers and {part['reference']} on {grid.describe()} "
              f"({engine} engine)")
        matrices, optima, sweep = sweep_scores(grid, evaluators, executor,
                                               part.get("chunk", CHUNK_POINTS))
        table = pd.concat([table, optima], axis=1)
        table = pd.concat([table, robot_serves(table, evaluators, workers)], axis=1)
        for name, frame in analyse(table, matrices, grid, part).items():
            atomic_write_csv(frame, folder / f"{name}.csv")
        return {"grid": grid.describe(), **sweep}

    run_part("population", results / "population", part, work,
             seeds={k: part[v] for k, v in SEEDS.items()}, force=force)


def main() -> None:
    parser = study_parser(__doc__, ROOT)
    parser.add_argument("--engine", choices=ENGINES, default="local",
                        help="where the landscapes are swept: the local pool, or Ray with "
                        "--workers CPUs (default: local)")
    parser.add_argument("--address", help="a running Ray cluster: auto or HOST:PORT "
                        "(with --engine ray; default: start a local instance)")
    parser.add_argument("--size", type=int, help="workers to draw (default: the config's)")

    def prepare(args, config: dict) -> tuple[dict, dict]:
        if args.size is not None:
            config["population"]["size"] = args.size
        return config, {"engine": args.engine, "address": args.address}

    study_main(run, __doc__, ROOT, parser, prepare)


if __name__ == "__main__":
    main()
