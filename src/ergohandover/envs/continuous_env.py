"""The handover-location search with continuous actions: moves of up to a few cells per axis,
for learners whose policies output real vectors (SAC)."""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from ..errors import ConfigError, UsageError
from .handover_env import HandoverEnv
from .scores import ScoreSource

MAX_MOVE = 5
"""Cells an action of ±1 moves along an axis. With the 10-1,000 evaluations a personalisation
may spend, a one-cell step (the discrete env's) leaves most of the grid out of reach: 5 cells
cross the 1 cm grid's longest axis (73 cells) in 15 steps and its shortest (31) in 6, while
a policy can still make single-cell moves (|a| ≈ 0.2)."""


class ContinuousHandoverEnv(HandoverEnv):
    """Move a box handover location by a real-valued step to minimise an ergonomic score.

    ## Description
    :class:`HandoverEnv`'s problem (same grid, scores, reward, starts, episode end and
    rendering) with a continuous action, for actor-critic learners such as SAC.

    ## Action Space
    ``Box(-1, 1, (3,), float32)``: the move along x, y and z as a fraction of ``max_move``
    cells (:data:`MAX_MOVE` by default); each component is rounded to whole cells
    (``round(a · max_move)``) and the new cell is clamped to the grid. Components outside
    [−1, 1] are clipped.

    ## Observation Space
    ``Box(0, 1, (4,), float32)``: the cell's position normalised per axis and the score divided
    by its largest value, 1 where infeasible (:class:`HandoverEnv`'s ``position``).

    ## Rewards
    :meth:`HandoverEnv.reward_of`: ``1/E² + S`` (the published code's symmetry term S), the
    infeasible reward (−1) where the twin cannot take the box.

    ## Starting State / Episode End
    As :class:`HandoverEnv` (a uniformly random cell; terminated at the target with
    ``episode_end="paper"``, never with ``"none"``; truncated by the registered ``TimeLimit``).

    ## Arguments
    scores, max_move, and every keyword of :class:`HandoverEnv` except ``observation``, which
    is always ``position``.

    ## Version History
    * v0: initial version.
    """

    def __init__(self, scores: ScoreSource | None = None, *, max_move: int = MAX_MOVE,
                 observation: str = "position", **kwargs):
        if observation != "position":
            raise ConfigError(f"observation = {observation!r} is not allowed (the continuous "
                              "env observes 'position')")
        if isinstance(max_move, bool) or not isinstance(max_move, int | np.integer) \
                or max_move < 1:
            raise ConfigError(f"max_move = {max_move!r} is outside the valid range (a whole "
                              "number of cells, at least 1)")
        super().__init__(scores, observation="position", **kwargs)
        self.max_move = int(max_move)
        self.action_space = spaces.Box(-1.0, 1.0, (3,), dtype=np.float32)
        self._high = np.asarray(self.shape) - 1

    def move(self, cell: int, action) -> int:
        """The flat cell reached from ``cell`` by ``action`` (3,) (no state kept)."""
        steps = np.rint(np.clip(action, -1.0, 1.0) * self.max_move).astype(int)
        index = np.clip(np.add(self.indices(cell), steps), 0, self._high)
        return int((index[0] * self._ny + index[1]) * self._nz + index[2])

    def step(self, action):
        if self.cell is None:
            raise UsageError("call reset() before step()")
        action = np.asarray(action, dtype=np.float64)
        if action.shape != (3,) or not np.all(np.isfinite(action)):
            raise ConfigError(f"action = {action.tolist()} is not 3 finite numbers")
        self.cell = cell = self.move(self.cell, action)
        score = self._score(cell)
        terminated = self._terminates and score <= self.target
        if self.render_mode == "human":
            self.render()
        return (self._observe(cell, score), self.reward_of(cell, score), terminated, False,
                self._info(cell, score))
