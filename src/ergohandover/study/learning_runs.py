"""The runs of the learning study: one job per (target, agent, budget, run), each with a seed
of its own, and what one run reports.

A *target* is a landscape, the objective the agents minimise on it and the cells that count as
the optimum (:mod:`..learning.targets`). A *budget* is either a number of env steps (score
evaluations), equal for every agent, or a wall-clock cap. Runs stop at their budget only, unless
the configuration asks for ``oracle_stop`` (stop when the target's score is seen: the known
optimum, which a learner in the field does not have).
"""

from __future__ import annotations

import math
import zlib
from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd

from ..envs.handover_env import HandoverEnv
from ..envs.scores import LandscapeScores, objective_values
from ..landscape.grid import Grid
from ..landscape.store import landscape_of
from ..learning.agents import agent, run_agent
from ..learning.rollouts import (
    network_policy,
    random_policy,
    roll_out,
    step_limit,
    table_policy,
)
from ..learning.targets import TargetCells, evaluations_to_target, target_cells
from ..learning.trace import Budget, best_locations
from ..twin.evaluate import Evaluator


@dataclass(frozen=True)
class RunJob:
    """One run of the study.

    Attributes:
        target: the target's name; ``evaluator`` and ``grid`` its landscape (read through the
            landscape door, once per process), ``objective`` and ``goal`` what the agents
            minimise and which cells count.
        agent: an agent of the registry (:data:`~..learning.agents.AGENTS`).
        budget: the budget's name; ``steps`` or ``time_cap_s`` its size.
        run: the run's number within its (target, agent, budget).
        seed: the run's own seed (:func:`run_seed`).
        oracle_stop: stop at the target's score.
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
    oracle_stop: bool = False
    episode_end: str = "none"
    rollouts: int = 0
    rollout_seed: int = 0


def run_seed(study_seed: int, target: str, agent: str, budget: str, run: int) -> int:
    """A seed of its own for every run of every agent, budget and target: drawn from the
    study's seed and the names (not positions), so adding a target changes no other run."""
    name = zlib.crc32(f"{target}|{agent}|{budget}".encode())
    return int(np.random.SeedSequence([study_seed, name, run]).generate_state(1)[0])


def rollout_seed(study_seed: int, target: str) -> int:
    """The seed of a target's rollout starts: the same starts for every agent (paired)."""
    return int(np.random.SeedSequence([study_seed, zlib.crc32(target.encode()), 1 << 20])
               .generate_state(1)[0])


_TARGETS: dict[tuple, tuple[LandscapeScores, TargetCells]] = {}


def target_of(evaluator: Evaluator, grid: Grid, objective: str,
              goal: str) -> tuple[LandscapeScores, TargetCells]:
    """The score table the agents read and the target cells, built once per process (a worker
    runs many jobs on one landscape)."""
    landscape = landscape_of(evaluator, grid, progress=False)
    key = (landscape.key, objective, goal)
    if key not in _TARGETS:
        scores = LandscapeScores(landscape, objective)
        _TARGETS[key] = scores, target_cells(HandoverEnv(scores),
                                             objective_values(landscape, objective), goal)
    return _TARGETS[key]


def run_job(job: RunJob) -> dict:
    """Run one job; returns its row of ``runs.csv`` and its trace."""
    scores, target = target_of(job.evaluator, job.grid, job.objective, job.goal)
    env = HandoverEnv(scores, observation=agent(job.agent).observation,
                      episode_end=job.episode_end)
    budget = Budget(job.time_cap_s, job.steps,
                    stop_score=target.score if job.oracle_stop else None)
    result, _ = run_agent(job.agent, env, budget, job.seed)
    reached_at = evaluations_to_target(result, target)
    found = best_locations(result, env.location)
    row = {k: v for k, v in asdict(job).items()
           if k not in ("evaluator", "grid", "rollout_seed")}
    row.update(
        target_score=target.score, best_score=result.best_score,
        found_x=found["x"].iloc[0] if len(found) else math.nan,
        found_y=found["y"].iloc[0] if len(found) else math.nan,
        found_z=found["z"].iloc[0] if len(found) else math.nan,
        reached=reached_at is not None,
        evaluations_to_target=math.nan if reached_at is None else reached_at,
        evaluations=result.steps, elapsed_s=round(result.elapsed_s, 3),
        steps_per_s=round(result.steps / max(result.elapsed_s, 1e-9)),
        stopped_by=result.stopped_by)
    if job.rollouts:
        row.update(rollouts_of(job, env, result, target))
    return {"row": row, "trace": result.trace}


def rollouts_of(job: RunJob, env: HandoverEnv, result, target: TargetCells) -> dict:
    """Greedy rollouts of the run's final policy (the random walk's for ``randomwalk``) from
    the target's shared starts; the rollouts' own ties are broken with the run's seed."""
    kind = agent(job.agent).policy
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


def trace_table(done: list[dict]) -> pd.DataFrame:
    """Every run's trace in one long table, keyed by target, agent, budget and run."""
    frames = [d["trace"].assign(**{k: d["row"][k] for k in ("target", "agent", "budget", "run")})
              for d in done]
    table = pd.concat(frames, ignore_index=True)
    keys = ["target", "agent", "budget", "run"]
    return table[keys + [c for c in table.columns if c not in keys]]
