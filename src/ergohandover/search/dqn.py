"""DQN (stable-baselines3) on the same env, with the position observation and the same caps.

The paper names Deep Q-learning as future work. This is SB3's DQN with a small MLP; torch and
SB3 are imported inside :func:`run_dqn` only, so the package and the env never load them.
SB3 seeds Python's, numpy's and torch's global generators from ``seed`` (its own design); this
is the only place in the package where a global RNG is touched.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..envs.handover_env import EPISODE_STEPS, HandoverEnv
from ..errors import ConfigError
from .record import BLOCK, Budget, Progress, Record
from .sb3_run import learn_within


@dataclass(frozen=True)
class DQNConfig:
    """Hyperparameters (SB3 defaults unless a reason is given).

    Args:
        net_arch: hidden layers: [64, 64] for a 4-number input (position and score) and 6
            actions; larger nets only slow the ~1,000 steps/s a CPU gives.
        learning_rate: Adam step (SB3 default 1e-4 is tuned for Atari; 1e-3 suits a small MLP
            on a low-dimensional input).
        buffer_size: replay transitions (1e5: ~minutes of experience, ~2 MB).
        learning_starts: random steps before the first update (enough to fill a batch with
            varied cells).
        batch_size: transitions per update.
        gamma: discount (the paper's 0.9, as for the tabular learner).
        train_freq: env steps per gradient update (SB3 default 4).
        target_update_interval: env steps between target-network copies (1,000: the rewards
            are short-horizon at γ 0.9).
        exploration_steps: steps over which ε falls linearly from 1 to ``exploration_final_eps``
            (absolute, so a time-capped run explores as a step-capped one).
        exploration_final_eps: the final ε.
        episode_steps: truncation of an episode (as the tabular learner).
        threads: torch threads (1: the run uses one core like the tabular learner).
    """

    net_arch: tuple[int, ...] = (64, 64)
    learning_rate: float = 1e-3
    buffer_size: int = 100_000
    learning_starts: int = 1_000
    batch_size: int = 64
    gamma: float = 0.9
    train_freq: int = 4
    target_update_interval: int = 1_000
    exploration_steps: int = 20_000
    exploration_final_eps: float = 0.05
    episode_steps: int = EPISODE_STEPS
    threads: int = 1


def run_dqn(env, budget: Budget, seed: int, config: DQNConfig | None = None,
            progress: Progress | None = None) -> Record:
    """Train SB3's DQN on ``env`` until the budget is spent; keep the lowest score seen.

    Args:
        env: a :class:`HandoverEnv` with ``observation="position"`` (unwrapped or wrapped).
        budget: time and/or step cap (steps = env steps).
        seed: SB3's seed and the env's starts.
        config: hyperparameters.
        progress: called every :data:`BLOCK` steps.

    Returns:
        The result; ``model`` holds the trained SB3 model.
    """
    from stable_baselines3 import DQN

    cfg = config or DQNConfig()
    base: HandoverEnv = env.unwrapped
    if base.observation != "position":
        raise ConfigError("DQN needs the env's observation = 'position' (got "
                         f"{base.observation!r})")

    def make(watched, total: int, env_seed: int):
        return DQN("MlpPolicy", watched, learning_rate=cfg.learning_rate,
                   buffer_size=cfg.buffer_size, learning_starts=cfg.learning_starts,
                   batch_size=cfg.batch_size, gamma=cfg.gamma, train_freq=cfg.train_freq,
                   target_update_interval=cfg.target_update_interval,
                   exploration_fraction=min(1.0, cfg.exploration_steps / total),
                   exploration_final_eps=cfg.exploration_final_eps,
                   policy_kwargs={"net_arch": list(cfg.net_arch)}, seed=env_seed,
                   device="cpu", verbose=0)

    return learn_within("dqn", base, make, budget, seed, cfg.episode_steps, cfg.threads, BLOCK,
                        progress)
