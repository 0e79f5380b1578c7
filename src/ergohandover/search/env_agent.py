"""The learners and walks of the handover environment as searchers: the one adapter.

A learner (tabular Q-learning, DQN, SAC) or a walk (the random walk, random draws,
hill-climbing) moves through the grid in its own loop over a
:class:`~ergohandover.envs.HandoverEnv` (or the continuous-action env, for SAC). Its run is
:func:`run_qlearning`-shaped: ``runner(env, budget, seed, config, progress) -> Record``. Here it
becomes a :class:`~.protocol.Searcher`:

- counted in env *steps* (the learning study, ``train``): :meth:`EnvAgent.drive` runs it on the
  score source as it is, every step a score read, repeats included;
- counted in *evaluations* (the personalisation study): :meth:`EnvAgent.search` runs it on the
  source seen through :class:`~.protocol.Evaluations`, so a step back onto a cell already scored
  is free, as a searcher's repeat is, and the run ends when the evaluations are spent.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

import numpy as np

from ..envs.handover_env import EPISODE_STEPS, HandoverEnv
from ..envs.scores import ScoreSource
from ..landscape.grid import Grid
from .cells import prior_point
from .prior import Prior
from .protocol import ASKS_PER_EVALUATION, Evaluations, Searcher
from .record import Budget, Progress, Record


class EvaluatedScores(ScoreSource):
    """A score source read through a search's :class:`~.protocol.Evaluations`."""

    def __init__(self, evaluations: Evaluations, objective: str):
        self.grid, self.objective, self.evaluations = evaluations.grid, objective, evaluations

    def score(self, flat: int) -> float:
        return self.evaluations.score(flat)


def attribute(path: str) -> Any:
    """``module:name``, imported when first needed (torch, SB3 and Optuna load only with the
    searcher that uses them); ``.module`` is a module of this package."""
    module, _, name = path.partition(":")
    return getattr(import_module(module, __package__ if module.startswith(".") else None), name)


class EnvAgent(Searcher):
    """An agent of the environment; see the module.

    Args:
        grid, seed, prior: as every searcher's; with a prior, every episode starts at the
            prior's cell (its location snapped into the grid) instead of a random one.
        name: its registry name.
        runner: ``module:function`` of its run (:func:`attribute`).
        config: ``module:Class`` of its settings (None: it has none), made with
            ``episode_steps`` and ``options``.
        observation: what the env shows it (``indices``, ``position``, or ``continuous``: the
            continuous-action env).
        options: its settings beyond the defaults (Q-learning's temperature).
        episode_end: the env's (``none``: only by truncation; ``paper``: also at ``target``).
        target: the score that ends an episode with ``episode_end`` ``paper`` (None: the
            env's default, the paper's).
        episode_steps: steps after which an episode is cut and restarted at a random cell.
    """

    unit = "steps"

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None, *, name: str,
                 runner: str, config: str | None = None, observation: str = "indices",
                 options: dict | None = None, episode_end: str = "none",
                 target: float | None = None, episode_steps: int = EPISODE_STEPS):
        super().__init__(grid, seed, prior)
        self.name, self.runner, self.observation = name, runner, observation
        self.episode_end, self.target = episode_end, target
        self.config = (None if config is None else
                       attribute(config)(episode_steps=episode_steps, **(options or {})))

    def env(self, scores: ScoreSource) -> HandoverEnv:
        """The env it runs on, over ``scores``."""
        given = {"episode_end": self.episode_end}
        if self.target is not None:
            given["target"] = self.target
        if self.prior is not None:
            centre = np.rint(prior_point(self.grid, self.prior)[0]).astype(int)
            given["start"] = tuple(int(v) for v in centre)
        if self.observation == "continuous":
            from ..envs.continuous_env import ContinuousHandoverEnv

            return ContinuousHandoverEnv(scores, **given)
        return HandoverEnv(scores, observation=self.observation, **given)

    def drive(self, scores: ScoreSource, budget: Budget, progress: Progress | None) -> Record:
        record = attribute(self.runner)(self.env(scores), budget, self.seed, self.config,
                                        progress)
        record.searcher = self.name
        if self.config is not None:
            from dataclasses import asdict

            record.settings = asdict(self.config)
        return record

    def search(self, evaluations: Evaluations) -> dict:
        source = EvaluatedScores(evaluations, evaluations.source.objective)
        record = self.drive(source, Budget(steps=ASKS_PER_EVALUATION * evaluations.limit),
                            None)
        return {"steps": record.steps}
