"""One way to run any agent: the study, the ``train`` command and the benchmarks call
:func:`run_agent` with the agent's name, so that an agent is dispatched in one place."""

from __future__ import annotations

from ..envs.handover_env import EPISODE_STEPS
from ..errors import ConfigError
from .trace import Budget, Progress, RunResult

AGENTS = ("qlearning", "dqn", "randomwalk", "random", "hillclimb")
"""Tabular Q-learning (the paper's), DQN (stable-baselines3), a random walk with the learner's
moves and restarts, uniform random search and hill-climbing with random restarts."""
TEMPERATURES = ("fixed", "adaptive")


def run_agent(agent: str, env, budget: Budget, seed: int, temperature: str = "fixed",
              episode_steps: int = EPISODE_STEPS, progress: Progress | None = None,
              ) -> tuple[RunResult, object | None]:
    """Run ``agent`` on ``env`` within ``budget``.

    Args:
        agent: one of :data:`AGENTS`.
        env: a :class:`~ergohandover.envs.HandoverEnv` (``observation="position"`` for DQN).
        budget: time and/or step cap, optional stop score.
        seed: the run's seed.
        temperature: Q-learning's softmax temperature, ``fixed`` (0.7, the published code) or
            ``adaptive`` (the paper's text).
        episode_steps: episode truncation for the learners [steps].
        progress: called about every few thousand steps.

    Returns:
        The run's result and the agent's own configuration (None for the search baselines).
    """
    if agent == "qlearning":
        from .qlearning import QLearningConfig, run_qlearning

        config = QLearningConfig(temperature=temperature, episode_steps=episode_steps)
        return run_qlearning(env, budget, seed, config, progress), config
    if agent == "dqn":
        from .dqn import DQNConfig, run_dqn

        config = DQNConfig(episode_steps=episode_steps)
        return run_dqn(env, budget, seed, config, progress), config
    if agent == "randomwalk":
        from .search import run_randomwalk

        return run_randomwalk(env, budget, seed, episode_steps, progress), None
    if agent in ("random", "hillclimb"):
        from .search import run_hillclimb, run_random

        run = run_random if agent == "random" else run_hillclimb
        return run(env, budget, seed, progress), None
    raise ConfigError(f"agent = {agent!r} is not allowed (use {', '.join(AGENTS)})")
