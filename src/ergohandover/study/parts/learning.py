"""Study part `learning`: can the learners be told apart? Tabular Q-learning (fixed and adaptive
temperature), DQN, a random walk, uniform random sampling and hill-climbing (the agents the
configuration names, not every agent of the registry) get the same budgets on targets from
easy to as rare as the paper's, in paired runs: run r of a target has one seed for every agent.

Budgets are counted in score evaluations (env steps) matched to the paper's wall-clock caps
under three mappings: the paper's Unity evaluated its 3.4 M locations in ~3 h, ~315 per second,
so its 2- and 5-minute caps are ~37,800 and ~94,500 evaluations (``paper-2min``,
``paper-5min``); at a tenth and ten times that rate they are 3,780 to 945,000
(``paper-2min@31.5`` ... ``paper-5min@3150``).

Each agent but DQN runs ``runs`` times per target once, at its largest budget, and stops at its
first target cell: a run with a smaller cap is the first part of that run, and target cells are
at the objective's minimum, so every smaller budget is read from it with nothing changed
(:mod:`..learning_runs`). DQN (~0.4 ms a step) runs ``dqn_runs`` times on ``dqn_targets`` at the
paper's rate only. ``full_runs`` runs per agent and paper-rate budget go to the cap: the best
location the agent keeps and the greedy rollouts of its policy. Episodes end only by truncation
(``episode_end: none``): the paper's rule (end at a score of at most 4) tells the learner where
its landscape's optimum is and teaches the greedy policy to avoid it (docs/learning.md).

The paper's own protocol (10 runs at 2 and 5 minutes of wall clock, Q-learning and DQN) is
experiments/configs/paper.json: ``wall_caps_s`` on the ``wall_targets``.

Writes results/learning/: targets.csv (each target's cells), runs.csv (one row per target,
agent, budget and run), traces.csv (every search and wall run's best-so-far trace),
full_runs.csv (the runs that went to their cap: locations, rollouts), summary.csv (per target,
agent and budget: success rate with Wilson 95 % interval, median evaluations to the target),
comparisons.csv (each learner against the random walk and random sampling, run for run, Holm
over the whole family, an equivalence test, a verdict), power.csv (each test's power at the
numbers of runs), curves.csv (bootstrap bands), found.csv (the best location each agent kept),
manifest.json.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager
from functools import partial
from pathlib import Path

import pandas as pd
from tqdm import tqdm

from ...envs.handover_env import HandoverEnv
from ...envs.scores import LandscapeScores, objective_values
from ...io.atomic import atomic_write_csv
from ...landscape import Landscape
from ...landscape.grid import Grid
from ...learning.agents import LEARNERS, agent
from ...learning.targets import target_cells
from ...twin.evaluate import Evaluator
from ..config import LearningConfig, StepBudget, StudyConfig, Target, wall_budget_name
from ..engines import Engine
from ..learning_runs import RunJob, rollout_seed, run_job, run_seed, run_table, trace_table
from ..learning_summary import comparisons, curves, found_locations, power, summary
from ..resume import run_part
from ..script import duration
from . import landscape as landscape_part
from .shared import grid_of, landscape

STEPS_PER_S = {"dqn": 3_240, "qlearning": 657_000, "qlearning-adaptive": 634_000,
               "randomwalk": 2_720_000, "random": 5_440_000, "hillclimb": 1_370_000}
"""Speeds for the time estimate and the progress bar [steps/s] on one free core: the runs' own
times in the first default study with paired runs (``elapsed_s`` fitted against evaluations
and grid size), corrected for that machine's load (the runs' times summed to twice the part's
CPU time), then scaled by each agent's median speed over the same runs on the machine of the
committed study (DQN 2.49x, Q-learning 1.73x, its adaptive version 1.63x, the random walk
1.65x, hill-climbing 1.10x; random sampling, whose runs are too short to time, as the walk);
another agent is costed as the slower table learner."""
SEARCH_STEPS = {"dqn": 13_000, "qlearning": 56_500, "qlearning-adaptive": 55_700,
                "randomwalk": 61_100, "random": 3_400, "hillclimb": 6_700}
"""Mean evaluations of a search run stopped at the target (capped by its budget) over the
default targets in that study: what a search run costs besides its start."""
JOB_OVERHEAD_S = {"dqn": 1.5, "other": 0.01}
"""A run's cost besides its steps [s]: starting the agent (SB3 builds its networks), the
rollouts, handing the result back to the pool."""
SERIAL_S = 25.0
"""The part's work outside the pool [s]: reading the targets' landscapes, the tables (the
power's exact sums, the bootstrap bands)."""


def target_model(config: StudyConfig, target: Target) -> tuple[Evaluator, Grid]:
    """A target's evaluator (its worker, the study's task with its gaze) and grid (its own
    boundary and step, else the landscape part's)."""
    evaluator = config.evaluator(target.worker, target.gaze)
    return evaluator, grid_of(evaluator, target.grid.boundary or config.landscape.boundary,
                              target.grid.step or config.landscape.step)


CHEAP = ("qlearning", "qlearning-adaptive", "randomwalk", "random", "hillclimb")
"""Agents whose step costs microseconds and whose run with a smaller step cap is the first part
of the run with a larger one (tests/test_learning_power.py): they run at every budget, from
one run at the largest. Any other agent (DQN, ~0.4 ms a step) is run as DQN is: ``dqn_runs``
runs on ``dqn_targets`` at the paper's rate."""


def cheap(name: str) -> bool:
    """Whether agent ``name`` is one of :data:`CHEAP`."""
    return name in CHEAP


def budgets_of(learning: LearningConfig, name: str) -> list[StepBudget]:
    """The step budgets an agent is reported at: every one, DQN's at the paper's rate only."""
    return learning.step_budgets(None if cheap(name) else learning.PAPER_RATE)


def plan_jobs(config: StudyConfig) -> list[RunJob]:
    """Every run of the study, the longest first (so that the pool ends together)."""
    learning = config.learning
    jobs = []
    for target in learning.targets:
        evaluator, grid = target_model(config, target)
        for name in learning.agents:
            if cheap(name) or target.name in learning.dqn_targets:
                jobs += agent_jobs(learning, target, evaluator, grid, name)
    return sorted(jobs, key=job_seconds, reverse=True)


def agent_jobs(learning: LearningConfig, target: Target, evaluator: Evaluator, grid: Grid,
               name: str) -> list[RunJob]:
    """One agent's runs on one target: its search runs at its largest step budget, its full
    runs at each paper-rate budget (none for DQN) and its runs under each wall-clock cap."""
    job = partial(RunJob, target.name, evaluator, grid, target.objective, target.goal, name,
                  oracle_stop=learning.oracle_stop, episode_end=learning.episode_end,
                  rollout_seed=rollout_seed(learning.seed, target.name))
    seed = partial(run_seed, learning.seed, target.name)
    runs = learning.runs if cheap(name) else learning.dqn_runs
    budgets = budgets_of(learning, name)
    jobs = []
    if budgets:
        largest = budgets[-1]
        jobs += [job(largest.name, largest.steps, None, run, seed(run), "search")
                 for run in range(runs)]
    paper = learning.step_budgets(learning.PAPER_RATE) if cheap(name) else []
    for budget in paper:
        rollouts = learning.rollouts if budget == paper[-1] and agent(name).policy else 0
        jobs += [job(budget.name, budget.steps, None, run, seed(run), "full", rollouts=rollouts)
                 for run in range(learning.full_runs)]
    if target.name in learning.wall_targets:
        jobs += [job(wall_budget_name(cap), None, cap, run, seed(run), "wall")
                 for cap in learning.wall_caps_s for run in range(runs)]
    return jobs


def job_seconds(job: RunJob) -> float:
    """A rough wall time of one job [s], for ordering and the estimate: its steps (a search
    run's typical ones when it stops at the target) at its agent's speed, plus its start."""
    # A tabular learner's Q-table is allocated once per process and zeroed after each run
    # (learning/qlearning.py), so it costs a run nothing more than its steps.
    overhead = JOB_OVERHEAD_S.get(job.agent, JOB_OVERHEAD_S["other"])
    if job.time_cap_s is not None:
        return job.time_cap_s + overhead
    steps = job.steps
    if job.kind == "search" and job.oracle_stop:
        steps = min(steps, SEARCH_STEPS.get(job.agent, steps))
    return steps / STEPS_PER_S.get(job.agent, STEPS_PER_S["qlearning"]) + overhead


def estimate_s(config: StudyConfig, workers: int) -> float:
    """The part's rough wall time on ``workers`` processes [s] (its landscapes cached)."""
    return sum(job_seconds(j) for j in plan_jobs(config)) / max(1, workers) + SERIAL_S


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
    agents (the tables' and figures' order), then budgets by evaluations and runs."""
    learning = config.learning
    budget_order = [b.name for b in learning.step_budgets()]
    budget_order += [wall_budget_name(cap) for cap in sorted(learning.wall_caps_s)]
    order = {name: i for i, name in enumerate([*targets["target"], *learning.agents])}
    order.update({name: i for i, name in enumerate(budget_order)})
    rank = lambda column: column.map(order) if column.name in ("target", "agent", "budget") \
        else column  # noqa: E731
    keys = ["target", "agent", "budget", "run"]
    runs = run_table(done, lambda name: budgets_of(learning, name)).sort_values(
        keys, key=rank, kind="stable", ignore_index=True)
    traces = trace_table(done).sort_values([*keys, "step"], key=rank, kind="stable",
                                           ignore_index=True)
    full = pd.DataFrame([d["row"] for d in done if d["kind"] != "search"])
    if not full.empty:
        full = full.sort_values(keys, key=rank, kind="stable", ignore_index=True)
    searches = pd.DataFrame([d["row"] for d in done if d["kind"] == "search"])
    if not searches.empty:
        searches = searches.sort_values(keys, key=rank, kind="stable", ignore_index=True)
    learners = tuple(a for a in learning.agents if a in LEARNERS)
    versus = comparisons(runs, learners, learning.margin, learning.alpha)
    sizes = {"every agent but DQN": learning.runs}
    if "dqn" in set(runs["agent"]):
        sizes["DQN"] = learning.dqn_runs
    return {"runs": runs, "traces": traces, "full_runs": full, "summary": summary(runs, full),
            "comparisons": versus,
            "power": power(sizes, max(1, len(versus)), learning.margin, learning.alpha),
            "curves": curves(searches, traces, learning.seed),
            "found": found_locations(full, targets)}


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
        return {"runs": len(done), "rows": len(runs), "targets": len(targets),
                "agents": len(config.learning.agents), "successes": int(runs["reached"].sum())}

    return run_part("learning", results / "learning", config.part_inputs("learning"), work,
                    seeds={"study": config.learning.seed}, force=force, engine=engine)
