"""What the stable-baselines3 learners (DQN, SAC) share: a wrapper that records every cell the
learner reaches, and one driver that trains a model within the run's budget.

SB3 drives its own loop, so the budget is kept by a callback: it stops the learner at the step
cap, at the time cap (checked every ``check_every`` steps) or when the record says the run
reached its stop score or cells. torch is imported inside :func:`learn_within` only.
"""

from __future__ import annotations

from collections.abc import Callable

import gymnasium as gym

from .qlearning import seeds_of
from .record import Budget, Progress, Record, Tracker

UNBOUNDED_STEPS = 10**9
"""``total_timesteps`` given to SB3 under a time cap only (the callback stops it first)."""


class Watch(gym.Wrapper):
    """Offers every cell the learner reaches (resets included) to the best-so-far record, so an
    SB3 learner's trace is the same as the other agents'.

    Args:
        env: the env the learner sees.
        best: the run's record.
    """

    def __init__(self, env, best: Tracker):
        super().__init__(env)
        self.best, self.steps = best, 0

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        if info["score"] <= self.best.best:
            self.best.offer(self.steps, info["score"], info["cell"])
        return obs, info

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        self.steps += 1
        if info["score"] <= self.best.best:
            self.best.offer(self.steps, info["score"], info["cell"])
        return obs, reward, terminated, truncated, info


ModelFactory = Callable[[gym.Env, int, int], object]
"""``make(env, total_timesteps, seed) -> model``: an SB3 model on the watched env."""


def learn_within(agent: str, base, make: ModelFactory, budget: Budget, seed: int,
                 episode_steps: int, threads: int, check_every: int,
                 progress: Progress | None = None) -> Record:
    """Train the model ``make`` builds on ``base`` (truncated after ``episode_steps``) until
    the budget is spent or its stop is reached; keep the lowest score seen.

    Args:
        agent: the agent's name (its result's).
        base: the unwrapped env.
        make: builds the model.
        budget: time and/or step cap (steps = env steps), optional stop.
        seed: the run's seed (the env's starts and SB3's generators).
        episode_steps: truncation of an episode.
        threads: torch threads.
        check_every: steps between clock checks and progress calls.
        progress: called every ``check_every`` steps.
    """
    import torch
    from stable_baselines3.common.callbacks import BaseCallback

    torch.set_num_threads(threads)
    best = Tracker.of(base.location, budget)
    watched = Watch(gym.wrappers.TimeLimit(base, episode_steps), best)

    class Caps(BaseCallback):
        def _on_step(self) -> bool:
            steps = self.num_timesteps
            if steps % check_every == 0:
                if progress:
                    progress(steps, best.elapsed())
                if best.elapsed() >= budget.time_limit:
                    return False
            return not best.reached and steps < budget.step_limit

    total = budget.steps if budget.steps is not None else UNBOUNDED_STEPS
    env_seed, _ = seeds_of(seed)
    model = make(watched, total, env_seed)
    model.learn(total_timesteps=total, callback=Caps(), progress_bar=False)
    if progress:
        progress(model.num_timesteps, best.elapsed())
    return best.finish(agent, model.num_timesteps, budget, {}, model=model)
