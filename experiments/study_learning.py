"""Study part `learning`: can the learners be told apart? Every agent — tabular Q-learning
(fixed and adaptive temperature), DQN, a random walk, uniform random sampling and hill-climbing
— gets the same budgets on targets from easy to as rare as the paper's, with a seed of its own
for every run, and no stop at the known optimum.

Usage: python experiments/study_learning.py [--config ...]

Episodes end only by truncation (``episode_end: none``, the default): the paper's rule (end at
a score of at most 4, ``episode_end: paper``) tells the learner where its landscape's optimum
is, means nothing for REBA, RULA or other workers, and with rewards that are all positive
teaches the greedy policy to avoid the target (docs/learning.md).

Budgets are counted in score evaluations (env steps) matched to the paper's wall-clock caps:
the paper's Unity evaluated its 3.4 M locations in ~3 h, ~315 per second, so its 2- and 5-minute
caps are ~37,800 and ~94,500 evaluations. Our own wall-clock caps are a second axis on some
targets. The paper's own protocol (10 runs at 2 and 5 minutes of wall clock) is
experiments/configs/paper.json.

Writes results/learning/: targets.csv (each target's cells), runs.csv (one row per run),
traces.csv (every run's best-so-far trace), summary.csv (per target, agent and budget: success
rate with Wilson 95 % interval, median evaluations to the target with censored runs),
comparisons.csv (each learner vs the random walk and random sampling), curves.csv (bootstrap
bands), found.csv (the best location each agent found), manifest.json.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import study_landscape
from tqdm import tqdm

from ergohandover.envs.handover_env import HandoverEnv
from ergohandover.envs.scores import LandscapeScores, objective_values
from ergohandover.executor import LocalExecutor
from ergohandover.io.atomic import atomic_write_csv
from ergohandover.landscape.cache import landscape_path
from ergohandover.learning.targets import target_cells
from ergohandover.study.learning_runs import (
    LEARNERS,
    RunJob,
    agent_and_temperature,
    rollout_seed,
    run_job,
    run_seed,
    trace_table,
)
from ergohandover.study.learning_summary import comparisons, curves, found_locations, summary
from ergohandover.study.parts import part_config, run_part, study_main
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.task import TaskSpec

ROOT = Path(__file__).resolve().parents[1]
STEPS_PER_S = {"dqn": 1_000, "other": 150_000}
"""Rough speeds for the time estimate [steps/s] (measured: bench_learning.py)."""
JOB_OVERHEAD_S = 0.5


def landscapes(config: dict, workers: int) -> dict[str, str]:
    """Each target's landscape file, swept into the cache when missing."""
    part = config["learning"]
    files = {}
    for target in part["targets"]:
        grid = {"boundary": config["landscape"]["boundary"], "step": config["landscape"]["step"],
                **target.get("grid", {})}
        body = BodySpec.from_percentile(target["worker"]) if "worker" in target else BodySpec()
        task = TaskSpec(gaze=target.get("gaze", config["landscape"].get("gaze", "on")))
        landscape = study_landscape.landscape_for(body, grid, workers, task=task)
        files[target["name"]] = str(landscape_path(landscape.key))
    return files


def budgets_of(part: dict, target: str) -> list[tuple[str, int | None, float | None]]:
    """(name, steps, time cap) of every budget a target's runs get."""
    out = [(name, int(steps), None) for name, steps in part["budgets"].items()]
    if target in part["wall_targets"]:
        out += [(f"wall-{cap:g}s", None, float(cap)) for cap in part["wall_caps_s"]]
    return out


def plan_jobs(part: dict, files: dict[str, str]) -> list[RunJob]:
    """Every run of the study, the longest first (so that the pool ends together)."""
    largest = max(part["budgets"].values(), default=None)
    jobs = []
    for target in part["targets"]:
        name = target["name"]
        for agent in part["agents"]:
            agent_and_temperature(agent)  # a bad name fails before anything runs
            if agent == "dqn" and name not in part["dqn_targets"]:
                continue
            for budget, steps, cap in budgets_of(part, name):
                rolls = (part["rollouts"] if steps is not None and steps == largest
                         and agent in (*LEARNERS, "randomwalk") else 0)
                jobs += [RunJob(name, files[name], target.get("objective", "paper_postural"),
                                target.get("goal", "minimum"), agent, budget, steps, cap, run,
                                run_seed(part["seed"], name, agent, budget, run),
                                part["oracle_stop"], part["episode_end"], rolls,
                                rollout_seed(part["seed"], name))
                         for run in range(part["runs"])]
    return sorted(jobs, key=job_seconds, reverse=True)


def job_seconds(job: RunJob) -> float:
    """A rough wall time of one job [s], for ordering and the estimate."""
    if job.time_cap_s is not None:
        return job.time_cap_s + JOB_OVERHEAD_S
    speed = STEPS_PER_S["dqn" if job.agent == "dqn" else "other"]
    return job.steps / speed + JOB_OVERHEAD_S


def estimate_s(config: dict, workers: int) -> float:
    """The part's rough wall time on ``workers`` processes [s] (its landscapes cached)."""
    part = config["learning"]
    files = {t["name"]: "" for t in part["targets"]}
    return sum(job_seconds(j) for j in plan_jobs(part, files)) / max(1, workers)


def target_table(config: dict, files: dict[str, str]) -> pd.DataFrame:
    """targets.csv: each target's landscape, objective, goal and cells."""
    rows = []
    from ergohandover.landscape.cache import Landscape

    for target in config["learning"]["targets"]:
        landscape = Landscape.load(Path(files[target["name"]]))
        objective = target.get("objective", "paper_postural")
        env = HandoverEnv(LandscapeScores(landscape, objective))
        cells = target_cells(env, objective_values(landscape, objective),
                             target.get("goal", "minimum"))
        rows.append({"target": target["name"], "objective": objective,
                     "goal": target.get("goal", "minimum"),
                     "worker": target.get("worker", "p50-male"),
                     "gaze": target.get("gaze", config["landscape"].get("gaze", "on")),
                     "grid": landscape.grid.describe(), "grid_cells": landscape.grid.size,
                     "score": cells.score, "cells": len(cells.cells), "fraction": cells.fraction,
                     "x": cells.location[0], "y": cells.location[1], "z": cells.location[2],
                     "landscape_key": landscape.key})
    return pd.DataFrame(rows)


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    study_landscape.run(config, results, workers)  # reused when finished
    part = part_config(config, "learning")

    def work(folder: Path) -> dict:
        files = landscapes(config, workers)
        targets = target_table(config, files)
        atomic_write_csv(targets, folder / "targets.csv")
        jobs = plan_jobs(part, files)
        print(f"  {len(jobs)} runs, estimated {estimate_s(config, workers) / 60:.0f} min on "
              f"{workers} workers")
        done = []
        with tqdm(total=len(jobs), desc="learning", unit="run") as bar:
            for result in LocalExecutor(workers).map(run_job, jobs):
                done.append(result)
                bar.update()
        # In the configuration's order of targets and agents (the tables' and figures' order).
        order = {name: i for i, name in enumerate([*targets["target"], *part["agents"]])}
        rank = lambda column: column.map(order) if column.name in ("target", "agent") \
            else column  # noqa: E731
        runs = pd.DataFrame([d["row"] for d in done]).sort_values(
            ["target", "agent", "budget", "run"], key=rank, kind="stable", ignore_index=True)
        traces = trace_table(done).sort_values(["target", "agent", "budget", "run", "step"],
                                               key=rank, kind="stable", ignore_index=True)
        atomic_write_csv(runs, folder / "runs.csv")
        atomic_write_csv(traces, folder / "traces.csv")
        table = summary(runs)
        atomic_write_csv(table, folder / "summary.csv")
        atomic_write_csv(comparisons(runs, tuple(a for a in part["agents"] if a in LEARNERS)),
                         folder / "comparisons.csv")
        atomic_write_csv(curves(runs, traces, part["seed"]), folder / "curves.csv")
        atomic_write_csv(found_locations(runs, targets), folder / "found.csv")
        return {"runs": len(runs), "targets": len(targets), "agents": len(part["agents"]),
                "successes": int(runs["reached"].sum())}

    run_part("learning", results / "learning", part, work, seeds={"study": part["seed"]},
             force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
