"""The env-driven agents (Q-learning, the random walk, SAC) measured like ask/tell searchers.

A learner walks the grid; the study of personalisation counts handovers. Here an agent of
:data:`~.agents.AGENTS` runs on a :class:`~ergohandover.envs.HandoverEnv` (or the continuous
one, for SAC) whose score source records every cell the first time it is scored, in order: the
same :class:`~.ask_tell.SearchRecord` a searcher's :func:`~.ask_tell.run_search` gives.

A step back onto a cell already scored counts no evaluation, exactly as a searcher's repeat
does: in a real session it would be a repeat handover, which a practitioner would not ask for.
The run ends once ``budget`` distinct cells were scored, or at the first score at or below
``stop_at``, or after ``STEPS_PER_EVALUATION × budget`` env steps (a learner that keeps to
known cells then has fewer evaluations in its record than its budget).
"""

from __future__ import annotations

from contextlib import suppress

import numpy as np

from ..envs.handover_env import EPISODE_STEPS
from ..envs.scores import ScoreSource
from ..errors import ConfigError
from ..landscape.grid import Grid
from .ask_tell import SearchRecord
from .trace import Budget

STEPS_PER_EVALUATION = 50
"""Env steps allowed per evaluation of the budget: a cap on revisits, far above what a learner
needs to reach new cells (a walk's step reaches a new cell about half the time or more)."""


class _Spent(Exception):
    """The run's evaluations are spent (raised through the agent's loop to end it)."""


class RecordingScores(ScoreSource):
    """Scores from an array that record each cell's first evaluation and end the run.

    Args:
        grid: the cells.
        scores: (grid.size,) the objective in flat order, ``inf`` where infeasible.
        budget: distinct cells that may be scored.
        stop_at: end once a score at or below it is scored (None: never).
        objective: the objective's name (the env's observation scale).
    """

    def __init__(self, grid: Grid, scores: np.ndarray, budget: int,
                 stop_at: float | None = None, objective: str = "paper_postural"):
        scores = np.asarray(scores, dtype=np.float64)
        if scores.shape != (grid.size,):
            raise ConfigError(f"scores: shape {scores.shape} does not match the grid's "
                              f"{grid.size} cells")
        self.grid, self.objective = grid, objective
        self._values = np.where(np.isnan(scores), np.inf, scores).tolist()
        self._budget, self._stop_at = budget, stop_at
        self.record = SearchRecord()
        self._seen: set[int] = set()

    def score(self, flat: int) -> float:
        self.record.asks += 1
        value = self._values[flat]
        if flat in self._seen:
            return value
        if len(self.record.cells) >= self._budget:
            raise _Spent
        self._seen.add(flat)
        self.record.cells.append(int(flat))
        self.record.scores.append(value)
        if self._stop_at is not None and value <= self._stop_at:
            raise _Spent
        return value


def env_search_record(agent_name: str, scores: np.ndarray, grid: Grid, budget: int, seed: int,
                      stop_at: float | None = None, objective: str = "paper_postural",
                      episode_end: str = "none",
                      episode_steps: int = EPISODE_STEPS) -> SearchRecord:
    """Run ``agent_name`` on ``scores`` until ``budget`` distinct cells were scored.

    Args:
        agent_name: an agent of :data:`~.agents.AGENTS` (``qlearning``, ``randomwalk``,
            ``sac``, ...).
        scores: (grid.size,) the objective, ``inf`` where infeasible.
        grid: the cells.
        budget: distinct evaluations.
        seed: the run's seed.
        stop_at: end at the first score at or below it (None: run the budget out).
        objective: the objective's name (the observation's scale).
        episode_end: the env's episode end (``none``, the learning study's, by default).
        episode_steps: episode truncation [steps].

    Returns:
        The distinct cells in the order first scored, their scores, and ``asks`` = every score
        the agent read (its steps and resets).
    """
    from .agents import agent_env, run_agent

    if budget < 1:
        raise ConfigError(f"budget = {budget} is outside the valid range (at least 1)")
    source = RecordingScores(grid, scores, budget, stop_at, objective)
    env = agent_env(agent_name, source, episode_end=episode_end)
    with suppress(_Spent):
        run_agent(agent_name, env, Budget(steps=STEPS_PER_EVALUATION * budget), seed,
                  episode_steps)
    return source.record
