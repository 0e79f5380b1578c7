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
from pathlib import Path

import numpy as np
import pandas as pd

from ..envs.handover_env import HandoverEnv
from ..envs.scores import LandscapeScores, objective_values
from ..errors import ConfigError
from ..landscape.cache import Landscape
from ..learning.rollouts import (
    network_policy,
    random_policy,
    roll_out,
    step_limit,
    table_policy,
)
from ..learning.runner import AGENTS, run_agent
from ..learning.targets import TargetCells, evaluations_to_target, target_cells
from ..learning.trace import Budget, best_locations

STUDY_AGENTS = ("qlearning", "qlearning-adaptive", "dqn", "randomwalk", "random", "hillclimb")
"""The study's agents: the runner's, with Q-learning under both temperatures as two agents."""
LEARNERS = ("qlearning", "qlearning-adaptive", "dqn")
"""Agents with a policy to roll out; the random walk is rolled out beside them."""


def agent_and_temperature(agent: str) -> tuple[str, str]:
    """The runner's agent and Q-learning temperature of a study agent."""
    if agent not in STUDY_AGENTS:
        raise ConfigError(f"agent = {agent!r} is not allowed (use {', '.join(STUDY_AGENTS)})")
    if agent == "qlearning-adaptive":
        return "qlearning", "adaptive"
    assert agent in AGENTS
    return agent, "fixed"


@dataclass(frozen=True)
class RunJob:
    """One run of the study.

    Attributes:
        target: the target's name; ``landscape`` its landscape file, ``objective`` and
            ``goal`` what the agents minimise and which cells count.
        agent: a study agent (:data:`STUDY_AGENTS`).
        budget: the budget's name; ``steps`` or ``time_cap_s`` its size.
        run: the run's number within its (target, agent, budget).
        seed: the run's own seed (:func:`run_seed`).
        oracle_stop: stop at the target's score.
        episode_end: the env's (``none``: episodes end only by truncation; ``paper``: also at
            a score of at most 4, the paper's rule).
        rollouts: greedy rollouts after the run (0: none); ``rollout_seed`` draws their starts.
    """

    target: str
    landscape: str
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


_CACHE: dict[tuple, object] = {}


def _cached(key: tuple, make):
    """One landscape, score table and target per process (a worker runs many jobs)."""
    if key not in _CACHE:
        _CACHE[key] = make()
    return _CACHE[key]


def target_of(landscape_file: str, objective: str, goal: str) -> tuple[LandscapeScores,
                                                                        TargetCells]:
    """The score table the agents read and the target cells, built once per process."""
    landscape = _cached(("landscape", landscape_file), lambda: Landscape.load(Path(
        landscape_file)))
    scores = _cached(("scores", landscape_file, objective),
                     lambda: LandscapeScores(landscape, objective))
    target = _cached(("target", landscape_file, objective, goal), lambda: target_cells(
        HandoverEnv(scores), objective_values(landscape, objective), goal))
    return scores, target


def run_job(job: RunJob) -> dict:
    """Run one job; returns its row of ``runs.csv`` and its trace."""
    scores, target = target_of(job.landscape, job.objective, job.goal)
    agent, temperature = agent_and_temperature(job.agent)
    env = HandoverEnv(scores, observation="position" if agent == "dqn" else "indices",
                      episode_end=job.episode_end)
    budget = Budget(job.time_cap_s, job.steps,
                    stop_score=target.score if job.oracle_stop else None)
    result, _ = run_agent(agent, env, budget, job.seed, temperature)
    reached_at = evaluations_to_target(result, target)
    found = best_locations(result, env.location)
    row = {k: v for k, v in asdict(job).items() if k not in ("landscape", "rollout_seed")}
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
    if job.agent == "randomwalk":
        policy = random_policy
    elif job.agent == "dqn":
        policy = network_policy(result.model, env)
    elif result.q_table is not None:
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
