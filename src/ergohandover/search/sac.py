"""Soft Actor-Critic (stable-baselines3) on the continuous-action env, with the same caps.

SAC outputs a real 3-vector: a move of up to a few cells per axis
(:class:`~ergohandover.envs.continuous_env.ContinuousHandoverEnv`), so it can cross the grid
within the tens to hundreds of handovers a personalisation may spend, where a one-cell learner
cannot. Its settings are SB3's defaults except where the budget calls for smaller numbers
(:class:`SACConfig`). torch and SB3 are imported inside :func:`run_sac` only; SB3 seeds the
global Python, numpy and torch generators from the seed (its design), as for DQN.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..envs.continuous_env import ContinuousHandoverEnv
from ..envs.handover_env import EPISODE_STEPS
from ..errors import ConfigError
from .record import Budget, Progress, Record
from .sb3_run import learn_within

CHECK_EVERY = 64
"""Steps between clock checks and progress updates: ~0.1-0.5 s of SAC (a few hundred steps/s),
so a time cap is kept to within a fraction of a second."""


@dataclass(frozen=True)
class SACConfig:
    """Hyperparameters (SB3 defaults unless a reason is given).

    Args:
        net_arch: hidden layers of actor and critics: [64, 64] (SB3: [256, 256]), as DQN's,
            for a 4-number input and a 3-number action; larger nets only slow each step.
        learning_rate: Adam step (SB3 default 3e-4).
        buffer_size: replay transitions (1e5: far beyond a run's 10-1,000 evaluations).
        learning_starts: uniformly random steps before the first update: 20 (SB3: 100), since
            a budget may be as small as 10-100 handovers and every step costs one.
        batch_size: transitions per update: 64 (SB3: 256), as the buffer holds only tens to
            hundreds of transitions when learning starts.
        gamma: discount (the paper's 0.9, as for the tabular learner and DQN).
        tau: soft target update (SB3 default 0.005).
        train_freq: env steps per update (1, SB3's default): learn from every handover.
        gradient_steps: updates per ``train_freq`` (SB3 default 1).
        ent_coef: entropy coefficient (SB3 default ``auto``: tuned towards a target entropy).
        episode_steps: truncation of an episode (as the other learners).
        threads: torch threads (1: one core, as every run).
    """

    net_arch: tuple[int, ...] = (64, 64)
    learning_rate: float = 3e-4
    buffer_size: int = 100_000
    learning_starts: int = 20
    batch_size: int = 64
    gamma: float = 0.9
    tau: float = 0.005
    train_freq: int = 1
    gradient_steps: int = 1
    ent_coef: str | float = "auto"
    episode_steps: int = EPISODE_STEPS
    threads: int = 1


def run_sac(env, budget: Budget, seed: int, config: SACConfig | None = None,
            progress: Progress | None = None) -> Record:
    """Train SB3's SAC on ``env`` until the budget is spent; keep the lowest score seen.

    Args:
        env: a :class:`ContinuousHandoverEnv` (unwrapped or wrapped).
        budget: time and/or step cap (steps = env steps).
        seed: SB3's seed and the env's starts.
        config: hyperparameters.
        progress: called every :data:`CHECK_EVERY` steps.

    Returns:
        The result; ``model`` holds the trained SB3 model.
    """
    from stable_baselines3 import SAC

    cfg = config or SACConfig()
    base = env.unwrapped
    if not isinstance(base, ContinuousHandoverEnv):
        raise ConfigError("SAC needs the continuous-action env (ContinuousHandoverEnv), got "
                          f"{type(base).__name__}")

    def make(watched, total: int, env_seed: int):
        return SAC("MlpPolicy", watched, learning_rate=cfg.learning_rate,
                   buffer_size=cfg.buffer_size, learning_starts=cfg.learning_starts,
                   batch_size=cfg.batch_size, gamma=cfg.gamma, tau=cfg.tau,
                   train_freq=cfg.train_freq, gradient_steps=cfg.gradient_steps,
                   ent_coef=cfg.ent_coef, policy_kwargs={"net_arch": list(cfg.net_arch)},
                   seed=env_seed, device="cpu", verbose=0)

    return learn_within("sac", base, make, budget, seed, cfg.episode_steps, cfg.threads,
                        CHECK_EVERY, progress)
