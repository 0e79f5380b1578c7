"""Study part `learning`: can the learners be told apart? Every agent of the registry — tabular
Q-learning (fixed and adaptive temperature), DQN, a random walk, uniform random sampling and
hill-climbing — gets the same budgets on targets from easy to as rare as the paper's, with a
seed of its own for every run, and no stop at the known optimum.

Episodes end only by truncation (``episode_end: none``, the default): the paper's rule (end at
a score of at most 4, ``episode_end: paper``) tells the learner where its landscape's optimum
is, means nothing for REBA, RULA or other workers, and with rewards that are all positive
teaches the greedy policy to avoid the target (docs/learning.md).

Budgets are counted in score evaluations (env steps) matched to the paper's wall-clock caps:
the paper's Unity evaluated its 3.4 M locations in ~3 h, ~315 per second, so its 2- and 5-minute
caps are ~37,800 and ~94,500 evaluations. Wall-clock caps are a second axis on some targets;
the paper's own protocol (10 runs at 2 and 5 minutes of wall clock, Q-learning and DQN) is
experiments/configs/paper.json.

Writes results/learning/: targets.csv (each target's cells), runs.csv (one row per run),
traces.csv (every run's best-so-far trace), summary.csv (per target, agent and budget: success
rate with Wilson 95 % interval, median evaluations to the target with censored runs),
comparisons.csv (each learner vs the random walk and random sampling), curves.csv (bootstrap
bands), found.csv (the best location each agent found), manifest.json.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pandas as pd
from tqdm import tqdm

from ...envs.handover_env import HandoverEnv
from ...envs.scores import LandscapeScores, objective_values
from ...io.atomic import atomic_write_csv
from ...landscape.cache import Landscape
from ...landscape.grid import Grid
from ...learning.agents import LEARNERS, agent
from ...learning.targets import target_cells
from ...twin.evaluate import Evaluator
from ..config import StudyConfig, Target, wall_budget_name
from ..engines import Engine
from ..learning_runs import RunJob, rollout_seed, run_job, run_seed, trace_table
from ..learning_summary import comparisons, curves, found_locations, summary
from ..resume import run_part
from ..script import duration
from . import landscape as landscape_part
from .shared import grid_of, landscape

STEPS_PER_S = {"dqn": 2_100, "other": 500_000}
"""Speeds for the time estimate and the progress bar [steps/s]: the medians of the committed
run's ``runs.csv`` on 2 cores (DQN 2,140-2,210; the others 0.43-1.9 M, their episodes' resets
included)."""
JOB_OVERHEAD_S = 0.05
"""A job's cost besides its steps [s]: starting the agent, the rollouts' bookkeeping (the
committed run: the part's wall time minus its runs' own time, per run)."""


def target_model(config: StudyConfig, target: Target) -> tuple[Evaluator, Grid]:
    """A target's evaluator (its worker, the study's task with its gaze) and grid (its own
    boundary and step, else the landscape part's)."""
    evaluator = config.evaluator(target.worker, target.gaze)
    return evaluator, grid_of(evaluator, target.grid.boundary or config.landscape.boundary,
                              target.grid.step or config.landscape.step)


def budgets_of(config: StudyConfig, target: str) -> list[tuple[str, int | None, float | None]]:
    """(name, steps, time cap) of every budget a target's runs get."""
    learning = config.learning
    out = [(name, steps, None) for name, steps in learning.budgets.items()]
    if target in learning.wall_targets:
        out += [(wall_budget_name(cap), None, cap) for cap in learning.wall_caps_s]
    return out


def plan_jobs(config: StudyConfig) -> list[RunJob]:
    """Every run of the study, the longest first (so that the pool ends together)."""
    learning = config.learning
    largest = max(learning.budgets.values(), default=None)
    jobs = []
    for target in learning.targets:
        evaluator, grid = target_model(config, target)
        for name in learning.agents:
            if name == "dqn" and target.name not in learning.dqn_targets:
                continue
            rolled = agent(name).policy is not None
            for budget, steps, cap in budgets_of(config, target.name):
                rolls = learning.rollouts if steps is not None and steps == largest \
                    and rolled else 0
                jobs += [RunJob(target.name, evaluator, grid, target.objective, target.goal,
                                name, budget, steps, cap, run,
                                run_seed(learning.seed, target.name, name, budget, run),
                                learning.oracle_stop, learning.episode_end, rolls,
                                rollout_seed(learning.seed, target.name))
                         for run in range(learning.runs)]
    return sorted(jobs, key=job_seconds, reverse=True)


def job_seconds(job: RunJob) -> float:
    """A rough wall time of one job [s], for ordering and the estimate."""
    if job.time_cap_s is not None:
        return job.time_cap_s + JOB_OVERHEAD_S
    speed = STEPS_PER_S["dqn" if job.agent == "dqn" else "other"]
    return job.steps / speed + JOB_OVERHEAD_S


def estimate_s(config: StudyConfig, workers: int) -> float:
    """The part's rough wall time on ``workers`` processes [s] (its landscapes cached)."""
    return sum(job_seconds(j) for j in plan_jobs(config)) / max(1, workers)


@contextmanager
def ticking(bar: tqdm, every_s: float = 1.0) -> Iterator[None]:
    """Redraw ``bar`` every ``every_s`` seconds while the block runs, so that its clock moves
    while a long run (a DQN run takes most of a minute) holds every worker."""
    stop = threading.Event()

    def tick() -> None:
        while not stop.wait(every_s):
            bar.refresh()  # tqdm's own lock keeps this from crossing an update

    clock = threading.Thread(target=tick, daemon=True)
    clock.start()
    try:
        yield
    finally:
        stop.set()
        clock.join()


def target_table(config: StudyConfig, found: dict[str, Landscape]) -> pd.DataFrame:
    """targets.csv: each target's landscape, objective, goal and cells."""
    rows = []
    for target in config.learning.targets:
        landscape = found[target.name]
        env = HandoverEnv(LandscapeScores(landscape, target.objective))
        cells = target_cells(env, objective_values(landscape, target.objective), target.goal)
        rows.append({"target": target.name, "objective": target.objective, "goal": target.goal,
                     "worker": target.worker, "gaze": target.gaze or config.landscape.gaze,
                     "grid": landscape.grid.describe(), "grid_cells": landscape.grid.size,
                     "score": cells.score, "cells": len(cells.cells), "fraction": cells.fraction,
                     "x": cells.location[0], "y": cells.location[1], "z": cells.location[2],
                     "landscape_key": landscape.key})
    return pd.DataFrame(rows)


def tables(config: StudyConfig, done: list[dict], targets: pd.DataFrame) -> dict:
    """The part's tables from its finished runs, in the configuration's order of targets and
    agents (the tables' and figures' order)."""
    learning = config.learning
    order = {name: i for i, name in enumerate([*targets["target"], *learning.agents])}
    rank = lambda column: column.map(order) if column.name in ("target", "agent") \
        else column  # noqa: E731
    runs = pd.DataFrame([d["row"] for d in done]).sort_values(
        ["target", "agent", "budget", "run"], key=rank, kind="stable", ignore_index=True)
    traces = trace_table(done).sort_values(["target", "agent", "budget", "run", "step"],
                                           key=rank, kind="stable", ignore_index=True)
    learners = tuple(a for a in learning.agents if a in LEARNERS)
    return {"runs": runs, "traces": traces, "summary": summary(runs),
            "comparisons": comparisons(runs, learners),
            "curves": curves(runs, traces, learning.seed),
            "found": found_locations(runs, targets)}


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    landscape_part.run(config, results, engine)  # reused when finished

    def work(folder: Path) -> dict:
        # Every target's landscape is read (or swept) here, before the pool starts, so that
        # its worker processes share them.
        found = {t.name: landscape(engine, *target_model(config, t))
                 for t in config.learning.targets}
        targets = target_table(config, found)
        atomic_write_csv(targets, folder / "targets.csv")
        jobs = plan_jobs(config)
        print(f"  {len(jobs)} runs, estimated {duration(estimate_s(config, engine.workers))} "
              f"on {engine.workers} workers")
        done = []
        # The bar counts estimated seconds of work, not runs: the runs differ 1,000-fold in
        # length and the longest go first, so a count of runs would promise hours at the start.
        cost = [job_seconds(job) for job in jobs]
        # The pool forks before the bar's clock thread starts (a fork copies no threads).
        with engine.executor() as executor, \
                tqdm(total=round(sum(cost), 1), desc="learning", unit="s", smoothing=0,
                     bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]"
                     ) as bar, ticking(bar):
            bar.set_description_str(f"learning (0/{len(jobs)} runs)")
            for index, result in executor.map_unordered(run_job, jobs):
                done.append(result)
                bar.set_description_str(f"learning ({len(done)}/{len(jobs)} runs)",
                                        refresh=False)
                bar.update(cost[index])
        written = tables(config, done, targets)
        for name, table in written.items():
            atomic_write_csv(table, folder / f"{name}.csv")
        runs = written["runs"]
        return {"runs": len(runs), "targets": len(targets), "agents": len(config.learning.agents),
                "successes": int(runs["reached"].sum())}

    return run_part("learning", results / "learning", config.part_inputs("learning"), work,
                    seeds={"study": config.learning.seed}, force=force, engine=engine)
