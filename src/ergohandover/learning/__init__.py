"""Agents that search the handover grid: tabular Q-learning (the paper's), DQN (stable-baselines3,
imported only when run) and the search baselines (random, hill-climbing, exhaustive)."""

from .trace import Budget, RunResult

__all__ = ["Budget", "RunResult"]
