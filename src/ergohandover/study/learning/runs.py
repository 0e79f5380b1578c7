"""The runs of the learning study and what one run reports.

A *target* is a landscape, the objective the agents minimise on it and the cells that count as
the optimum (:mod:`...search.targets`). A *budget* is a number of env steps (score
evaluations), equal for every agent, or a wall-clock cap. Three kinds of run:

- ``search``: one run per (target, agent, run) at the agent's largest step budget, stopped at
  its first target cell. An agent's run with a smaller step cap is the first part of the run
  with a larger one (its random numbers are drawn in blocks from its own Generators whatever
  the cap; ``tests/test_learning_power.py``), and every target cell is at the objective's
  minimum, so success, evaluations to the target and the best score at every smaller budget
  are read from this one run (:func:`budget_rows`) exactly as runs capped there would give
  them.
- ``full``: runs to a paper-rate budget without the stop: the best location an agent keeps
  (every cell at its best score, as the paper's learner does) and greedy rollouts of its
  policy, both of which need the whole run.
- ``wall``: runs to a wall-clock cap (the paper's own protocol), without the stop.

Run r of a target has one seed for every agent and budget (:func:`run_seed`): the agents meet
the same random starts and draw from the same streams, so they are compared run for run.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd

from ...envs.handover_env import HandoverEnv
from ...envs.scores import LandscapeScores, objective_values
from ...landscape import Landscape, landscape_key, landscape_of
from ...landscape.grid import Grid
from ...search import Budget, entry, make, run
from ...search.env_agent import EnvAgent
from ...search.record import best_locations
from ...search.rollouts import (
    network_policy,
    random_policy,
    roll_out,
    step_limit,
    table_policy,
)
from ...search.statistics import best_so_far
from ...search.targets import TargetCells, evaluations_to_target, target_cells
from ...twin.evaluate import Evaluator
from .config import StepBudget

KINDS = ("search", "full", "wall")


@dataclass(frozen=True)
class RunJob:
    """One run of the study.

    Attributes:
        target: the target's name; ``evaluator`` and ``grid`` its landscape (read through the
            landscape door, once per process), ``objective`` and ``goal`` what the agents
            minimise and which cells count.
        agent: a searcher of the registry (:data:`~...search.registry.SEARCHERS`).
        budget: the budget's name; ``steps`` or ``time_cap_s`` its size.
        run: the run's number within its target.
        seed: the run's seed (:func:`run_seed`: the same for every agent).
        kind: ``search``, ``full`` or ``wall`` (the module's docstring).
        oracle_stop: stop at the first target cell (search runs).
        episode_end: the env's (``none``: episodes end only by truncation; ``paper``: also at
            a score of at most 4, the paper's rule).
        rollouts: greedy rollouts after the run (0: none); ``rollout_seed`` draws their starts.
    """

    target: str
    evaluator: Evaluator
    grid: Grid
    objective: str
    goal: str
    agent: str
    budget: str
    steps: int | None
    time_cap_s: float | None
    run: int
    seed: int
    kind: str = "search"
    oracle_stop: bool = False
    episode_end: str = "none"
    rollouts: int = 0
    rollout_seed: int = 0


def run_seed(study_seed: int, target: str, run: int) -> int:
    """Run ``run``'s seed on ``target``: the same for every agent and budget (paired runs),
    drawn from the study's seed and the target's name (not its position), so adding a target
    or an agent changes no other run."""
    name = zlib.crc32(target.encode())
    return int(np.random.SeedSequence([study_seed, name, run]).generate_state(1)[0])


def rollout_seed(study_seed: int, target: str) -> int:
    """The seed of a target's rollout starts: the same starts for every agent (paired)."""
    return int(np.random.SeedSequence([study_seed, zlib.crc32(target.encode()), 1 << 20])
               .generate_state(1)[0])


_TARGETS: dict[tuple, tuple[LandscapeScores, TargetCells]] = {}
"""Each target's score table and cells by (landscape key, objective, goal): filled by the parent
(:func:`prepare_target`) before the pool forks, so that its workers inherit them."""


def prepare_target(landscape: Landscape, objective: str,
                   goal: str) -> tuple[LandscapeScores, TargetCells]:
    """The score table the agents read and the target cells of ``landscape``, kept for every
    run on it in this process and in the workers forked after."""
    key = (landscape.key, objective, goal)
    if key not in _TARGETS:
        scores = LandscapeScores(landscape, objective)
        _TARGETS[key] = scores, target_cells(HandoverEnv(scores),
                                             objective_values(landscape, objective), goal)
    return _TARGETS[key]


def target_of(evaluator: Evaluator, grid: Grid, objective: str,
              goal: str) -> tuple[LandscapeScores, TargetCells]:
    """A job's score table and target cells: the parent's (:func:`prepare_target`), or read
    through the landscape door in a process that has none."""
    found = _TARGETS.get((landscape_key(evaluator, grid), objective, goal))
    if found is not None:
        return found
    return prepare_target(landscape_of(evaluator, grid, progress=False), objective, goal)


def run_job(job: RunJob) -> dict:
    """Run one job; returns its ``kind``, its row (a run's outcome) and its trace."""
    scores, target = target_of(job.evaluator, job.grid, job.objective, job.goal)
    searcher = make(job.agent, job.grid, job.seed, episode_end=job.episode_end)
    stop = job.oracle_stop and job.kind == "search"
    budget = Budget.of(entry(job.agent).unit, job.steps, job.time_cap_s,
                       stop_score=target.score if stop else None,
                       stop_cells=target.mask if stop else None)
    result = run(searcher, scores, budget)
    reached_at = evaluations_to_target(result, target)
    row = {k: v for k, v in asdict(job).items()
           if k not in ("evaluator", "grid", "objective", "goal", "rollout_seed", "rollouts")}
    row.update(
        target_score=target.score, best_score=result.best_score,
        reached=reached_at is not None,
        evaluations_to_target=math.nan if reached_at is None else reached_at,
        evaluations=result.steps, elapsed_s=round(result.elapsed_s, 3),
        steps_per_s=round(result.steps / max(result.elapsed_s, 1e-9)),
        stopped_by=result.stopped_by)
    # The env the agent ran on (its observation, for a network's rollouts); a searcher's: the
    # plain one, for the locations.
    env = searcher.env(scores) if isinstance(searcher, EnvAgent) else HandoverEnv(scores)
    if job.kind != "search":  # the run kept every cell at its best score: the location
        found = best_locations(result, env.location)
        row.update({f"found_{axis}": found[axis].iloc[0] if len(found) else math.nan
                    for axis in "xyz"})
    if job.rollouts:
        row.update(rollouts_of(job, env, result, target))
    return {"kind": job.kind, "row": row, "trace": result.trace}


def rollouts_of(job: RunJob, env: HandoverEnv, result, target: TargetCells) -> dict:
    """Greedy rollouts of the run's final policy (the random walk's for ``randomwalk``) from
    the target's shared starts; the rollouts' own ties are broken with the run's seed."""
    kind = entry(job.agent).policy
    if kind == "random":
        policy = random_policy
    elif kind == "network":
        policy = network_policy(result.model, env)
    elif kind == "table" and result.q_table is not None:
        policy = table_policy(result.q_table, env.grid.size)
    else:
        return {}
    starts = np.random.default_rng(job.rollout_seed).integers(env.grid.size, size=job.rollouts)
    limit = step_limit(env)
    walks = roll_out(env, policy, target.mask, starts, limit,
                     np.random.default_rng([job.seed, 1]))
    return {"rollouts": job.rollouts, "rollout_limit": limit,
            "rollout_reached": int(walks.reached.sum()), "rollout_mean_steps": walks.mean_steps}


RUN_COLUMNS = ("target", "agent", "budget", "mapping", "cap_min", "steps", "time_cap_s", "run",
               "seed", "run_budget", "oracle_stop", "episode_end", "target_score", "best_score",
               "reached", "evaluations_to_target", "evaluations", "elapsed_s", "steps_per_s",
               "stopped_by")
"""runs.csv: one row per (target, agent, budget, run). ``run_budget`` names the run it is read
from (its trace's key); ``elapsed_s`` and ``steps_per_s`` are that run's."""


def budget_rows(row: dict, trace: pd.DataFrame, budgets: list[StepBudget]) -> list[dict]:
    """A search run's rows at each of ``budgets`` (each at most its own): reached when it first
    evaluated a target cell within the budget, its best score then from its trace, and the
    evaluations a run capped there (and stopped at the target) would have made."""
    at = np.array([b.steps for b in budgets])
    best = best_so_far(trace["step"].to_numpy(), trace["best_score"].to_numpy(), at)
    first = row["evaluations_to_target"]
    rows = []
    for budget, best_score in zip(budgets, best.tolist(), strict=True):
        reached = bool(first <= budget.steps)  # NaN (never) compares False
        rows.append({**row, "budget": budget.name, "mapping": budget.rate,
                     "cap_min": budget.cap_s / 60, "steps": budget.steps, "time_cap_s": math.nan,
                     "run_budget": row["budget"], "best_score": best_score, "reached": reached,
                     "evaluations_to_target": first if reached else math.nan,
                     "evaluations": min(row["evaluations"], budget.steps),
                     "stopped_by": "stop_score" if reached and row["stopped_by"] == "stop_score"
                     else "step_cap"})
    return rows


def wall_row(row: dict) -> dict:
    """A wall-clock-capped run's row of runs.csv (no mapping: its cap is of wall clock)."""
    return {**row, "mapping": math.nan, "cap_min": row["time_cap_s"] / 60, "steps": math.nan,
            "run_budget": row["budget"]}


def run_table(done: list[dict], budgets_of) -> pd.DataFrame:
    """runs.csv from the finished search and wall runs; ``budgets_of(agent)`` gives the step
    budgets an agent is reported at."""
    rows = []
    for d in done:
        if d["kind"] == "search":
            own = d["row"]["steps"]
            rows += budget_rows(d["row"], d["trace"],
                                [b for b in budgets_of(d["row"]["agent"]) if b.steps <= own])
        elif d["kind"] == "wall":
            rows.append(wall_row(d["row"]))
    return pd.DataFrame(rows, columns=list(RUN_COLUMNS))


def trace_table(done: list[dict]) -> pd.DataFrame:
    """The traces of the search and wall runs in one long table, keyed by target, agent, the
    run's own budget and run."""
    keys = ["target", "agent", "budget", "run"]
    frames = [d["trace"].assign(**{k: d["row"][k] for k in keys})
              for d in done if d["kind"] != "full"]
    if not frames:
        return pd.DataFrame(columns=keys)
    table = pd.concat(frames, ignore_index=True)
    return table[keys + [c for c in table.columns if c not in keys]]
