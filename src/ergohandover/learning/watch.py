"""The wrapper through which an SB3 learner's run is recorded: every cell it reaches."""

from __future__ import annotations

import gymnasium as gym

from .trace import BestSoFar


class Watch(gym.Wrapper):
    """Offers every cell the learner reaches (resets included) to the best-so-far record, so an
    SB3 learner's trace is the same as the other agents'.

    Args:
        env: the env the learner sees.
        best: the run's record.
    """

    def __init__(self, env, best: BestSoFar):
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
