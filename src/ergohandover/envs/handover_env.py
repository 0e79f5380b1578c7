"""The handover-location search as a Gymnasium environment (the paper's learning problem)."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import ClassVar

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ..errors import ConfigError, UsageError
from ..landscape import Landscape
from ..landscape.grid import DEFAULT_STEP, Grid
from ..sim import require_display
from ..twin.evaluate import Evaluator, posture_solver
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
RENDER_MODES = ("rgb_array", "human")
RENDER_FPS = 30
"""Frames a second of a rendered episode (a video's rate; ``human`` paces its window to it): one
step, 3 mm of box travel on the default grid, per frame."""
RENDER_SIZE = (480, 480)
"""Width and height [px] of an ``rgb_array`` frame: the study's pictures' side view."""
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
    default: :mod:`ergohandover.study.learning.part` says why).
    Truncation is left to the ``TimeLimit`` of :func:`~ergohandover.envs.register`
    (:data:`EPISODE_STEPS`).

    ## Rendering
    The scene at the current cell: the worker in its solved posture holding the box there, the
    dual-arm robot holding it too (at the first lift that can, else reaching for it), seen from
    the worker's left side as in the study's pictures (PyBullet, :mod:`~ergohandover.scene`).
    ``render_mode="rgb_array"``: :meth:`render` returns it as an (480, 480, 3) uint8 image
    (:data:`RENDER_SIZE`; TinyRenderer, headless, the same image for the same cell).
    ``render_mode="human"``: PyBullet's own window shows it, updated at every reset and step
    and paced to ``metadata["render_fps"]``; it needs a display (DISPLAY or WAYLAND_DISPLAY),
    without one the constructor refuses with a one-line error (``ergohandover view`` shows the
    scene in a browser). The window opens at the first frame; :meth:`close` closes it. The
    worker and box are ``evaluator``'s: by default an online source's own, else the default
    worker and box (a landscape does not record whose it is).

    ## Arguments
    scores: a :class:`~ergohandover.envs.scores.ScoreSource`; if omitted, ``landscape`` (a
    :class:`~ergohandover.landscape.sweep.Landscape` or its file), else online ``evaluate()`` on
    ``Grid(boundary, step)`` (paper-code boundary by default) for the default worker and box.
    objective, observation, episode_end, target, start, infeasible_reward, render_mode: see
    above. evaluator: the worker and box :meth:`render` shows (see Rendering).

    ``info``: ``score`` (``inf`` if infeasible), ``location`` (x, y, z) [m], ``cell`` (flat).

    ## Version History
    * v0: initial version; ``rgb_array`` and ``human`` rendering added without changing the
      dynamics.
    """

    metadata: ClassVar[dict] = {"render_modes": list(RENDER_MODES), "render_fps": RENDER_FPS}

    def __init__(self, scores: ScoreSource | None = None, *,
                 landscape: Landscape | str | Path | None = None,
                 objective: str = "paper_postural", observation: str = "indices",
                 episode_end: str = "paper", target: float = 4.0,
                 start: int | tuple[int, int, int] | None = None,
                 infeasible_reward: float = INFEASIBLE_REWARD,
                 boundary: Boundary | None = None, step: float = DEFAULT_STEP,
                 render_mode: str | None = None, evaluator: Evaluator | None = None):
        if render_mode is not None and render_mode not in RENDER_MODES:
            raise ConfigError(f"render_mode = {render_mode!r} is not allowed (use "
                              f"{' or '.join(RENDER_MODES)}, or None)")
        if render_mode == "human":  # refused now, not after the caller has set up a run
            require_display("render_mode = 'human'")
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
        self.render_mode = render_mode
        self.evaluator = evaluator or getattr(scores, "evaluator", None) or Evaluator()
        self._scene = None  # a SceneRenderer, opened by the first frame
        self._shown: int | None = None  # the cell the scene is posed at
        self._last_frame = 0.0  # when the window last changed [s, monotonic]

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
        if self.render_mode == "human":
            self.render()
        return self._observe(self.cell, score), self._info(self.cell, score)

    def step(self, action):
        if self.cell is None:
            raise UsageError("call reset() before step()")
        action = int(action)
        if not 0 <= action < len(ACTIONS):
            raise ConfigError(f"action = {action} is outside the valid range 0-5")
        self.cell, score, reward, terminated = self.transition(self.cell, action)
        if self.render_mode == "human":
            self.render()
        return (self._observe(self.cell, score), reward, terminated, False,
                self._info(self.cell, score))

    def render(self):
        """The scene at the current cell (see Rendering): an (H, W, 3) uint8 image for
        ``rgb_array``; ``None`` for ``human`` (the window shows it) and without a mode."""
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode: pass render_mode="
                            "'rgb_array' or 'human' to the constructor")
            return None
        if self.cell is None:
            raise UsageError("call reset() before render()")
        scene = self._posed_scene(self.cell)
        if self.render_mode == "rgb_array":
            from ..scene.scene_render import TARGET, VIEWS

            return np.asarray(scene.view(VIEWS["side"], size=RENDER_SIZE, target=TARGET))
        # Paced like Gymnasium's own human renderers: an agent's walk is watchable.
        time.sleep(max(0.0, self._last_frame + 1.0 / RENDER_FPS - time.monotonic()))
        self._last_frame = time.monotonic()
        return None

    def close(self) -> None:
        """Close the scene (and its window) if one was opened; the env stays usable."""
        if self._scene is not None:
            self._scene.world.close()
            self._scene, self._shown = None, None
        super().close()

    def _posed_scene(self, cell: int):
        """The scene (opened on first use, reopened if the user closed its window) posed at
        ``cell``: the worker's solved posture there and the robot's hold."""
        from ..scene.scene_render import TARGET, VIEWS, SceneRenderer
        from ..scene.world import WorkerPosture, World

        if self._scene is not None and not self._scene.world.connected:
            self._scene, self._shown = None, None
        if self._scene is None:
            ev = self.evaluator
            self._scene = SceneRenderer(World(ev.body, ev.task, gui=self.render_mode == "human"))
            self._scene.world.look_at(VIEWS["side"], TARGET)
        if self._shown != cell:
            location = np.array(self.location(cell))
            solver = posture_solver(self.evaluator)
            posture = WorkerPosture(solver.model.joint_names, solver.solve(location[None]).q[0])
            arms, lift = self._scene.world.hold_pose(location, posture)
            self._scene.pose(location, arms, posture, lift)
            self._shown = cell
        return self._scene

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
