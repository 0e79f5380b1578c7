"""The one registry of agents: ``train``, the learning study, the rollouts and the benchmarks
name an agent here and run it through :func:`run_agent`, so an agent is defined and dispatched
in one place.

Each :class:`Agent` says how it runs, what the env must show it (grid indices, or the position
and score for DQN's network) and what greedy policy its run leaves for the rollouts (a
Q-table, a network, the random walk's coin, or none for the searches).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..envs.handover_env import EPISODE_STEPS
from ..errors import ConfigError
from .trace import Budget, Progress, RunResult


@dataclass(frozen=True)
class Agent:
    """One agent of the registry.

    Attributes:
        name: its name on the command line and in every table.
        label: its name in figures and the report.
        observation: the env's observation it needs (``indices`` or ``position``).
        policy: what its run leaves to roll out greedily: ``table`` (a Q-table), ``network``
            (DQN), ``random`` (the random walk's uniform actions) or None (a search).
        temperature: Q-learning's softmax temperature (``fixed`` 0.7, the published code, or
            ``adaptive``, the paper's text); None for the other agents.
    """

    name: str
    label: str
    observation: str = "indices"
    policy: str | None = None
    temperature: str | None = None

    @property
    def learns(self) -> bool:
        """A learner: its policy comes from training (Q-learning, DQN)."""
        return self.policy in ("table", "network")


AGENTS: dict[str, Agent] = {a.name: a for a in (
    Agent("qlearning", "Q-learning (τ 0.7)", policy="table", temperature="fixed"),
    Agent("qlearning-adaptive", "Q-learning (adaptive τ)", policy="table",
          temperature="adaptive"),
    Agent("dqn", "DQN", observation="position", policy="network"),
    Agent("randomwalk", "random walk", policy="random"),
    Agent("random", "random sampling"),
    Agent("hillclimb", "hill-climbing"),
)}
"""Tabular Q-learning (the paper's; under the published code's fixed temperature and the text's
adaptive one), DQN (stable-baselines3), a random walk with the learner's moves and restarts,
uniform random sampling and hill-climbing with random restarts."""
LEARNERS = tuple(name for name, a in AGENTS.items() if a.learns)


def agent(name: str) -> Agent:
    """The registry's agent of ``name``; a one-line ConfigError for any other name."""
    if name not in AGENTS:
        raise ConfigError(f"agent = {name!r} is not allowed (use {', '.join(AGENTS)})")
    return AGENTS[name]


def run_agent(name: str, env, budget: Budget, seed: int, episode_steps: int = EPISODE_STEPS,
              progress: Progress | None = None) -> tuple[RunResult, object | None]:
    """Run agent ``name`` on ``env`` within ``budget``.

    Args:
        name: one of :data:`AGENTS`.
        env: a :class:`~ergohandover.envs.HandoverEnv` with the agent's ``observation``.
        budget: time and/or step cap, optional stop score.
        seed: the run's seed.
        episode_steps: episode truncation for the learners and the random walk [steps].
        progress: called about every few thousand steps.

    Returns:
        The run's result and the agent's own configuration (None for the searches).
    """
    spec = agent(name)
    if spec.policy == "table":
        from .qlearning import QLearningConfig, run_qlearning

        config = QLearningConfig(temperature=spec.temperature, episode_steps=episode_steps)
        return run_qlearning(env, budget, seed, config, progress), config
    if spec.policy == "network":
        from .dqn import DQNConfig, run_dqn

        config = DQNConfig(episode_steps=episode_steps)
        return run_dqn(env, budget, seed, config, progress), config
    if spec.policy == "random":
        from .search import run_randomwalk

        return run_randomwalk(env, budget, seed, episode_steps, progress), None
    from .search import run_hillclimb, run_random

    search = run_random if name == "random" else run_hillclimb
    return search(env, budget, seed, progress), None
