"""Study part `learning`: can the learners be told apart? Tabular Q-learning (fixed and adaptive
temperature), DQN, a random walk, random draws and hill-climbing (the agents the
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
(:mod:`.runs`). DQN (a network update a step) runs ``dqn_runs`` times on ``dqn_targets``
at the paper's rate only. ``full_runs`` runs per agent and paper-rate budget go to the cap: the best
location the agent keeps and the greedy rollouts of its policy. Episodes end only by truncation
(``episode_end: none``): the paper's rule (end at a score of at most 4) tells the learner where its
landscape's optimum is and teaches the greedy policy to avoid it (docs/learning.md).

The paper's own protocol (10 runs at 2 and 5 minutes of wall clock, Q-learning and DQN) is
experiments/configs/paper.json: ``wall_caps_s`` on the ``wall_targets``.

Writes results/learning/: targets.csv (each target's cells), runs.csv (one row per target,
agent, budget and run), traces.csv (every search and wall run's best-so-far trace),
full_runs.csv (the runs that went to their cap: locations, rollouts), summary.csv (per target,
agent and budget: success rate with Wilson 95 % interval, median evaluations to the target),
comparisons.csv (each learner against the random walk and random draws, run for run, Holm
over the whole family, an equivalence test, a verdict), power.csv (each test's power at the
numbers of runs), curves.csv (bootstrap bands), found.csv (the best location each agent kept),
manifest.json.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from pathlib import Path

import pandas as pd

from ...io.atomic import atomic_write_csv
from ...landscape import Landscape
from ...landscape.grid import Grid
from ...search.registry import LEARNERS, entry
from ...twin.evaluate import Evaluator
from ..config import StudyConfig, wall_budget_name
from ..engines import Engine
from ..resume import run_part
from ..script import duration
from ..shared import grid_of, landscape, run_jobs
from .config import LearningConfig, StepBudget, Target
from .runs import (
    RunJob,
    prepare_target,
    rollout_seed,
    run_job,
    run_seed,
    run_table,
    trace_table,
)
from .summary import comparisons, curves, found_locations, power, summary


@dataclass(frozen=True)
class Speeds:
    """What each agent's runs cost, as its runs in a finished learning part took them: its
    median speed [steps/s] and the mean steps of a search run stopped at its target (capped by
    its budget). An agent without such runs is not measured, and nothing is guessed for it."""

    steps_per_s: dict[str, float]
    search_steps: dict[str, float]

    @classmethod
    def read(cls, folder: Path) -> Speeds:
        """The speeds of the part's runs.csv in ``folder`` (none if there is none)."""
        try:
            runs = pd.read_csv(folder / "runs.csv")
        except (OSError, ValueError):
            return cls({}, {})
        runs = runs[runs["steps_per_s"] > 0]
        own = runs[runs["budget"] == runs["run_budget"]]  # a search run's own row
        return cls(runs.groupby("agent")["steps_per_s"].median().to_dict(),
                   own.groupby("agent")["evaluations"].mean().to_dict())

    def measured(self, jobs: list[RunJob]) -> bool:
        return all(job.agent in self.steps_per_s for job in jobs)


def target_model(config: StudyConfig, target: Target) -> tuple[Evaluator, Grid]:
    """A target's evaluator (its worker, the study's task with its gaze) and grid (its own
    boundary and step, else the landscape part's)."""
    evaluator = config.evaluator(target.worker, target.gaze)
    return evaluator, grid_of(evaluator, target.grid.boundary or config.landscape.boundary,
                              target.grid.step or config.landscape.step)


CHEAP = ("qlearning", "qlearning-adaptive", "randomwalk", "random-draws", "hillclimb")
"""Agents whose step costs microseconds and whose run with a smaller step cap is the first part
of the run with a larger one (tests/test_learning_power.py): they run at every budget, from
one run at the largest. Any other agent (DQN: a network update a step) is run as DQN is:
``dqn_runs`` runs on ``dqn_targets`` at the paper's rate."""


def cheap(name: str) -> bool:
    """Whether agent ``name`` is one of :data:`CHEAP`."""
    return name in CHEAP


def budgets_of(learning: LearningConfig, name: str) -> list[StepBudget]:
    """The step budgets an agent is reported at: every one, DQN's at the paper's rate only."""
    return learning.step_budgets(None if cheap(name) else learning.PAPER_RATE)


def plan_jobs(config: StudyConfig, speeds: Speeds | None = None) -> list[RunJob]:
    """Every run of the study, the longest first at ``speeds`` (so that the pool ends
    together), else the most steps first."""
    learning = config.learning
    jobs = []
    for target in learning.targets:
        evaluator, grid = target_model(config, target)
        for name in learning.agents:
            if cheap(name) or target.name in learning.dqn_targets:
                jobs += agent_jobs(learning, target, evaluator, grid, name)
    if speeds is None or not speeds.measured(jobs):
        return sorted(jobs, key=lambda j: j.time_cap_s or j.steps, reverse=True)
    return sorted(jobs, key=partial(job_seconds, speeds=speeds), reverse=True)


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
        rollouts = learning.rollouts if budget == paper[-1] and entry(name).policy else 0
        jobs += [job(budget.name, budget.steps, None, run, seed(run), "full", rollouts=rollouts)
                 for run in range(learning.full_runs)]
    if target.name in learning.wall_targets:
        jobs += [job(wall_budget_name(cap), None, cap, run, seed(run), "wall")
                 for cap in learning.wall_caps_s for run in range(runs)]
    return jobs


def job_seconds(job: RunJob, speeds: Speeds) -> float:
    """A job's wall time [s] at its agent's measured speed (its steps, or a search run's
    typical ones when it stops at the target); a job of an agent not measured counts 1 s."""
    if job.time_cap_s is not None:
        return job.time_cap_s
    rate = speeds.steps_per_s.get(job.agent)
    if rate is None:
        return 1.0
    steps = job.steps
    if job.kind == "search" and job.oracle_stop:
        steps = min(steps, speeds.search_steps.get(job.agent, steps))
    return steps / rate


def estimate_s(config: StudyConfig, workers: int, folder: Path) -> float | None:
    """The part's runs' wall time on ``workers`` processes [s] at the speeds of the runs in
    ``folder`` (a finished learning part), or None where an agent was never measured."""
    speeds, jobs = Speeds.read(folder), plan_jobs(config)
    if not speeds.measured(jobs):
        return None
    return sum(job_seconds(j, speeds) for j in jobs) / max(1, workers)


def target_table(config: StudyConfig, found: dict[str, Landscape]) -> pd.DataFrame:
    """targets.csv: each target's landscape, objective, goal and cells (computed here once, for
    this process and the workers it forks: :func:`~.runs.prepare_target`)."""
    rows = []
    for target in config.learning.targets:
        landscape = found[target.name]
        _, cells = prepare_target(landscape, target.objective, target.goal)
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

    def work(folder: Path) -> dict:
        # Every target's landscape is read (or swept) here, before the pool starts, so that
        # its worker processes share them.
        found = {t.name: landscape(engine, *target_model(config, t))
                 for t in config.learning.targets}
        targets = target_table(config, found)
        atomic_write_csv(targets, folder / "targets.csv")
        speeds = Speeds.read(results / "learning")  # the last run's, before it is replaced
        jobs = plan_jobs(config, speeds)
        measured = speeds.measured(jobs)
        cost = [job_seconds(job, speeds) if measured else 1.0 for job in jobs]
        took = (f"about {duration(sum(cost) / max(1, engine.workers))} at the last run's speeds"
                if measured else "not measured yet")
        print(f"  {len(jobs)} runs on {engine.workers} workers: {took}")
        # The bar counts estimated seconds of work where the speeds are known, not runs: the
        # runs differ 1,000-fold in length and the longest go first, so a count of runs would
        # promise hours at the start.
        done = run_jobs(engine, run_job, jobs, "learning", cost)
        written = tables(config, done, targets)
        for name, table in written.items():
            atomic_write_csv(table, folder / f"{name}.csv")
        runs = written["runs"]
        return {"runs": len(done), "rows": len(runs), "targets": len(targets),
                "agents": len(config.learning.agents), "successes": int(runs["reached"].sum())}

    return run_part("learning", results / "learning", config.part_inputs("learning"), work,
                    seeds={"study": config.learning.seed}, force=force, engine=engine)
