"""The one registry of agents: ``train``, the learning study, the rollouts and the benchmarks
name an agent here and run it through :func:`run_agent`, so an agent is defined and dispatched
in one place.

Each :class:`Agent` says how it runs, what the env must show it (grid indices, the position
and score for DQN's network, or the continuous-action env for SAC) and what greedy policy its
run leaves for the rollouts (a Q-table, a network, the random walk's coin, or none for the
searches). The ask/tell searchers of :mod:`.searchers` (Bayesian optimisation, TPE, CMA-ES,
PSO, the population prior) are agents too: one step is one distinct evaluation.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..envs.handover_env import EPISODE_STEPS, HandoverEnv
from ..envs.scores import ScoreSource
from ..errors import ConfigError
from .prior import Prior
from .trace import Budget, Progress, RunResult


@dataclass(frozen=True)
class Agent:
    """One agent of the registry.

    Attributes:
        name: its name on the command line and in every table.
        label: its name in figures and the report.
        observation: the env's observation it needs (``indices`` or ``position``), or
            ``continuous``: the continuous-action env (``ContinuousHandoverEnv``, which
            observes the position).
        policy: what its run leaves to roll out greedily: ``table`` (a Q-table), ``network``
            (DQN), ``actor`` (SAC's continuous actor: no rollout over the discrete moves),
            ``random`` (the random walk's uniform actions) or None (a search).
        temperature: Q-learning's softmax temperature (``fixed`` 0.7, the published code, or
            ``adaptive``, the paper's text); None for the other agents.
        searcher: an ask/tell searcher of :data:`~.ask_tell.SEARCHERS` of the same name,
            driven against the env's score source (one step = one distinct evaluation).
    """

    name: str
    label: str
    observation: str = "indices"
    policy: str | None = None
    temperature: str | None = None
    searcher: bool = False

    @property
    def learns(self) -> bool:
        """A learner: its policy comes from training (Q-learning, DQN, SAC)."""
        return self.policy in ("table", "network", "actor")


AGENTS: dict[str, Agent] = {a.name: a for a in (
    Agent("qlearning", "Q-learning (τ 0.7)", policy="table", temperature="fixed"),
    Agent("qlearning-adaptive", "Q-learning (adaptive τ)", policy="table",
          temperature="adaptive"),
    Agent("dqn", "DQN", observation="position", policy="network"),
    Agent("randomwalk", "random walk", policy="random"),
    Agent("random", "random sampling"),
    Agent("hillclimb", "hill-climbing"),
    Agent("sac", "SAC", observation="continuous", policy="actor"),
    Agent("bo", "Bayesian optimisation (GP)", searcher=True),
    Agent("tpe", "TPE", searcher=True),
    Agent("cmaes", "CMA-ES", searcher=True),
    Agent("pso", "particle swarm", searcher=True),
    Agent("prior", "population prior", searcher=True),
)}
"""Tabular Q-learning (the paper's; under the published code's fixed temperature and the text's
adaptive one), DQN (stable-baselines3), a random walk with the learner's moves and restarts,
uniform random sampling, hill-climbing with random restarts, SAC (stable-baselines3) on the
continuous-action env, and the ask/tell searchers: Bayesian optimisation (Optuna's GP sampler),
TPE, CMA-ES, particle-swarm optimisation and the population prior alone (which needs a
worker's prior)."""
LEARNERS = tuple(name for name, a in AGENTS.items() if a.learns)


def agent(name: str) -> Agent:
    """The registry's agent of ``name``; a one-line ConfigError for any other name."""
    if name not in AGENTS:
        raise ConfigError(f"agent = {name!r} is not allowed (use {', '.join(AGENTS)})")
    return AGENTS[name]


def agent_env(name: str, scores: ScoreSource, **kwargs) -> HandoverEnv:
    """The env agent ``name`` runs on, over ``scores``: a :class:`HandoverEnv` with the agent's
    observation, or the continuous-action env for ``continuous``; ``kwargs`` go to the env
    (``episode_end``, ``target``, ...)."""
    spec = agent(name)
    if spec.observation == "continuous":
        from ..envs.continuous_env import ContinuousHandoverEnv

        return ContinuousHandoverEnv(scores, **kwargs)
    return HandoverEnv(scores, observation=spec.observation, **kwargs)


def run_agent(name: str, env, budget: Budget, seed: int, episode_steps: int = EPISODE_STEPS,
              progress: Progress | None = None,
              prior: Prior | None = None) -> tuple[RunResult, object | None]:
    """Run agent ``name`` on ``env`` within ``budget``.

    Args:
        name: one of :data:`AGENTS`.
        env: the agent's env (:func:`agent_env`), possibly wrapped.
        budget: time and/or step cap, optional stop score.
        seed: the run's seed.
        episode_steps: episode truncation for the learners and the random walk [steps].
        progress: called about every few thousand steps (every evaluation for a searcher).
        prior: the worker's prior, for the searchers (the ``prior`` searcher needs one; the
            others use it as a warm start); the learners ignore it.

    Returns:
        The run's result and the agent's own configuration (None for the searches).
    """
    spec = agent(name)
    if spec.searcher:
        from .searcher_runs import run_searcher

        return run_searcher(name, env, budget, seed, progress, prior), None
    if spec.policy == "actor":
        from .sac import SACConfig, run_sac

        config = SACConfig(episode_steps=episode_steps)
        return run_sac(env, budget, seed, config, progress), config
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
