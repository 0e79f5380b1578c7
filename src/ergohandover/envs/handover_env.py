"""The handover-location search as a Gymnasium environment (the paper's learning problem)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import ClassVar

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ..errors import ConfigError, UsageError
from ..landscape.cache import Landscape
from ..landscape.grid import DEFAULT_STEP, Grid
from ..twin.task import Boundary
from .scores import SCORE_MAX, LandscapeScores, OnlineScores, ScoreSource, check_objective

ACTIONS = ("+x", "-x", "+y", "-y", "+z", "-z")
"""The paper's action order: action i moves one grid step along the named axis."""
OBSERVATIONS = ("indices", "position")
EPISODE_ENDS = ("paper", "none")
EPISODE_STEPS = 10_000
"""Registered truncation [steps]. The paper's episodes end only on reaching the target; on a
landscape where the target is never reached that is one endless episode, so random restarts need
a cap. 10,000 steps is ~20x the grid's Manhattan diameter (476 cells) and 0.1-0.2 s of the
tabular learner."""
INFEASIBLE_REWARD = -1.0
"""Reward for moving onto an infeasible location: below every feasible reward (which lie in
(-0.08, 1]), so that it is learned as the worst outcome."""
SYMMETRY_WEIGHT = 0.5
SYMMETRY_OFFSET = 0.001  # [m]; both from the published code


def symmetry_term(x: float) -> float:
    """The published code's symmetry reward −0.5·(d − 0.001)², d = 2·|x| [m].

    Args:
        x: lateral offset of the box centre from the worker's midline [m].
    """
    d = 2.0 * abs(x)
    return -SYMMETRY_WEIGHT * (d - SYMMETRY_OFFSET) ** 2


class HandoverEnv(gym.Env):
    """Move a box handover location on a grid around the worker to minimise an ergonomic score.

    ## Description
    Amani & Akhavian's learning problem: the state is a cell of a 3-D grid of box-centre
    locations in the worker frame (x right, y up, z forward; default the published code's
    boundary x ±0.20, y 0.72-1.44, z 0.30-0.60 m every 3 mm, 134 x 241 x 101 cells). Each step
    moves the box one cell; the worker's digital twin takes the box and its posture is scored.

    ## Action Space
    ``Discrete(6)``, the paper's order: 0 +x, 1 −x, 2 +y, 3 −y, 4 +z, 5 −z. A move off the
    grid is clamped (the box stays).

    ## Observation Space
    ``observation="indices"`` (default): ``MultiDiscrete(grid.shape)``, the cell's (i, j, k).
    ``observation="position"``: ``Box(0, 1, (4,), float32)``, the cell's position normalised
    to [0, 1] per axis and the score divided by its largest possible value
    (:data:`~ergohandover.envs.scores.SCORE_MAX`), 1 where infeasible; the input of the DQN.

    ## Rewards
    ``1/E² + S`` with E the objective at the new cell (``paper_postural`` by default; ``reba``,
    ``reba_ab`` or ``rula``) and the published code's symmetry term
    ``S = −0.5·(d − 0.001)²``, d = 2·|x| [m]. Moving onto an infeasible location (hand misses
    the handle, box in the body, unbalanced) gives ``infeasible_reward`` (−1) and the box stays
    there: the learner sees where infeasibility is, as it would in the simulator.

    ## Starting State
    A uniformly random cell (the paper's), drawn from ``self.np_random``; it may be infeasible
    (1.1% of the default grid). ``start`` (or ``reset(options={"start": ...})``) fixes it: a
    flat index or an (i, j, k) tuple.

    ## Episode End
    ``episode_end="paper"``: terminated when the score is at most ``target`` (4, the paper's
    optimum; the twin's own minimum on a grid is in its landscape's statistics, e.g.
    ``results/landscape/stats.csv``). ``episode_end="none"``: never terminated (the study's
    default: :mod:`ergohandover.study.parts.learning` says why).
    Truncation is left to the ``TimeLimit`` of :func:`~ergohandover.envs.register`
    (:data:`EPISODE_STEPS`).

    ## Arguments
    scores: a :class:`~ergohandover.envs.scores.ScoreSource`; if omitted, ``landscape`` (a
    :class:`~ergohandover.landscape.sweep.Landscape` or its file), else online ``evaluate()`` on
    ``Grid(boundary, step)`` (paper-code boundary by default) for the default worker and box.
    objective, observation, episode_end, target, start, infeasible_reward: see above.

    ``info``: ``score`` (``inf`` if infeasible), ``location`` (x, y, z) [m], ``cell`` (flat).

    ## Version History
    * v0: initial version.
    """

    metadata: ClassVar[dict] = {"render_modes": []}

    def __init__(self, scores: ScoreSource | None = None, *,
                 landscape: Landscape | str | Path | None = None,
                 objective: str = "paper_postural", observation: str = "indices",
                 episode_end: str = "paper", target: float = 4.0,
                 start: int | tuple[int, int, int] | None = None,
                 infeasible_reward: float = INFEASIBLE_REWARD,
                 boundary: Boundary | None = None, step: float = DEFAULT_STEP):
        if observation not in OBSERVATIONS:
            raise ConfigError(f"observation = {observation!r} is not allowed (use "
                             f"{' or '.join(OBSERVATIONS)})")
        if episode_end not in EPISODE_ENDS:
            raise ConfigError(f"episode_end = {episode_end!r} is not allowed (use "
                             f"{' or '.join(EPISODE_ENDS)})")
        if scores is None:
            scores = _default_scores(landscape, check_objective(objective), boundary, step)
        self.scores = scores
        self.grid: Grid = scores.grid
        self.objective = scores.objective
        self.observation = observation
        self.episode_end = episode_end
        self.target = float(target)
        self.infeasible_reward = float(infeasible_reward)
        self.action_space = spaces.Discrete(len(ACTIONS))
        nx, ny, nz = self.shape = self.grid.shape
        if observation == "indices":
            self.observation_space = spaces.MultiDiscrete(np.array(self.shape), dtype=np.int64)
        else:
            self.observation_space = spaces.Box(0.0, 1.0, (4,), dtype=np.float32)
        # Plain Python numbers and lists: the transition runs millions of times per run.
        self._stride_x, self._nx, self._ny, self._nz = ny * nz, nx, ny, nz
        self._axes = [a.tolist() for a in self.grid.axes()]
        self._symmetry = [symmetry_term(x) for x in self._axes[0]]
        self._score = scores.score
        self._terminates = episode_end == "paper"
        self._score_max = float(SCORE_MAX[self.objective])
        self.start = None if start is None else self.flat(start)
        self.cell: int | None = None

    # -- the transition: shared by step() and the learners' fast path --------------------------
    def transition(self, cell: int, action: int) -> tuple[int, float, float, bool]:
        """Move from ``cell`` by ``action`` (no state kept): the env's one transition.

        The tabular learner and the search baselines call this directly on
        ``env.unwrapped`` (what :meth:`step` does without building arrays), so both run the
        same code.

        Returns:
            The new flat cell, its score (``inf`` if infeasible), the reward and whether the
            episode terminates there.
        """
        nz = self._nz
        if action == 0:
            if cell // self._stride_x < self._nx - 1:
                cell += self._stride_x
        elif action == 1:
            if cell >= self._stride_x:
                cell -= self._stride_x
        elif action == 2:
            if (cell // nz) % self._ny < self._ny - 1:
                cell += nz
        elif action == 3:
            if (cell // nz) % self._ny > 0:
                cell -= nz
        elif action == 4:
            if cell % nz < nz - 1:
                cell += 1
        elif cell % nz > 0:
            cell -= 1
        score = self._score(cell)
        return (cell, score, self.reward_of(cell, score),
                self._terminates and score <= self.target)

    def reward(self, cell: int) -> float:
        """The reward for arriving at ``cell`` (as :meth:`transition` computes it)."""
        return self.reward_of(cell, self._score(cell))

    def reward_of(self, cell: int, score: float) -> float:
        """The reward ``1/E² + S`` for arriving at ``cell`` with objective ``score`` (the one
        place it is computed); :attr:`infeasible_reward` where the score is infinite."""
        if score == math.inf:
            return self.infeasible_reward
        return 1.0 / (score * score) + self._symmetry[cell // self._stride_x]

    def rewards_of(self, scores: np.ndarray) -> np.ndarray:
        """:meth:`reward_of` for every cell at once: ``scores`` (grid.size,) in flat order,
        ``inf`` where infeasible; the same floats as the per-cell method."""
        scores = np.asarray(scores, dtype=np.float64)
        symmetry = np.repeat(np.asarray(self._symmetry), self._stride_x)
        with np.errstate(divide="ignore"):
            rewards = 1.0 / (scores * scores) + symmetry
        return np.where(np.isinf(scores), self.infeasible_reward, rewards)

    # -- Gymnasium API ------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        start = (options or {}).get("start", self.start)
        self.cell = (int(self.np_random.integers(self.grid.size)) if start is None
                     else self.flat(start))
        score = self._score(self.cell)
        return self._observe(self.cell, score), self._info(self.cell, score)

    def step(self, action):
        if self.cell is None:
            raise UsageError("call reset() before step()")
        action = int(action)
        if not 0 <= action < len(ACTIONS):
            raise ConfigError(f"action = {action} is outside the valid range 0-5")
        self.cell, score, reward, terminated = self.transition(self.cell, action)
        return (self._observe(self.cell, score), reward, terminated, False,
                self._info(self.cell, score))

    # -- helpers --------------------------------------------------------------------------------
    def flat(self, cell: int | tuple[int, int, int]) -> int:
        """A flat index from a flat index or (i, j, k); ValueError if outside the grid."""
        if isinstance(cell, tuple | list | np.ndarray) and len(cell) == 3:
            i, j, k = (int(c) for c in cell)
            if not all(0 <= c < n for c, n in zip((i, j, k), self.shape, strict=True)):
                raise ConfigError(f"start = {tuple(cell)} is outside the grid {self.shape}")
            return (i * self._ny + j) * self._nz + k
        flat = int(cell)
        if not 0 <= flat < self.grid.size:
            raise ConfigError(f"start = {flat} is outside the valid range 0-{self.grid.size - 1}")
        return flat

    def indices(self, cell: int) -> tuple[int, int, int]:
        """(i, j, k) of a flat cell."""
        ij, k = divmod(cell, self._nz)
        i, j = divmod(ij, self._ny)
        return i, j, k

    def location(self, cell: int) -> tuple[float, float, float]:
        """The box centre of a flat cell, worker frame [m]."""
        i, j, k = self.indices(cell)
        return self._axes[0][i], self._axes[1][j], self._axes[2][k]

    def observe(self, cell: int) -> np.ndarray:
        """The observation at a flat cell (what :meth:`step` returns on arriving there)."""
        return self._observe(cell, self._score(cell))

    def _observe(self, cell: int, score: float) -> np.ndarray:
        i, j, k = self.indices(cell)
        if self.observation == "indices":
            return np.array((i, j, k), dtype=np.int64)
        s = 1.0 if score == math.inf else min(score, self._score_max) / self._score_max
        return np.array((i / (self._nx - 1), j / (self._ny - 1), k / (self._nz - 1), s),
                        dtype=np.float32)

    def _info(self, cell: int, score: float) -> dict:
        return {"score": score, "location": self.location(cell), "cell": cell}


def _default_scores(landscape, objective: str, boundary, step: float) -> ScoreSource:
    if landscape is not None:
        if not isinstance(landscape, Landscape):
            landscape = Landscape.load(Path(landscape))
        return LandscapeScores(landscape, objective)
    return OnlineScores(Grid(boundary or Boundary.paper_code(), step), objective=objective)
