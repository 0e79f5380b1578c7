"""Search baselines on the learners' budget: a random walk (the learner's moves and restarts
without the learning), uniform random search, greedy hill-climbing with random restarts, and
exhaustive search (the landscape's minimum: the ground truth)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..envs.handover_env import EPISODE_STEPS, HandoverEnv
from ..landscape import Landscape
from ..landscape.stats import optimum
from .qlearning import seeds_of
from .trace import BLOCK, BestSoFar, Budget, Progress, RunResult, finish


def run_randomwalk(env, budget: Budget, seed: int, episode_steps: int = EPISODE_STEPS,
                  progress: Progress | None = None) -> RunResult:
    """Walk the grid with uniformly random actions: Q-learning's moves, episode ends and random
    restarts, without the learning (what the tabular learner does while its Q-table is flat).

    Args:
        env: a :class:`HandoverEnv` (possibly wrapped; its transition is used directly).
        budget: time and/or step cap (one step = one transition, as for the learners).
        seed: the run's seed (the env's starts and the agent's actions, as Q-learning's).
        episode_steps: steps after which an episode is cut and restarted at a random cell.
        progress: called every :data:`BLOCK` steps.
    """
    base: HandoverEnv = env.unwrapped
    env_seed, rng = seeds_of(seed)
    env.reset(seed=env_seed)
    transition, score_of = base.transition, base.scores.score
    cell = base.cell
    best = BestSoFar(base.location, budget.stop_score, budget.stop_cells)
    done = best.offer(0, score_of(cell), cell)
    step_limit, time_limit = budget.step_limit, budget.time_limit
    steps, best_score, in_episode, episodes = 0, best.best, 0, 1
    while not done and steps < step_limit and best.elapsed() < time_limit:
        for a in rng.integers(6, size=int(min(BLOCK, step_limit - steps))).tolist():
            cell, s, _, terminated = transition(cell, a)
            steps += 1
            in_episode += 1
            if s <= best_score:
                best_score = s
                if best.offer(steps, s, cell):
                    done = True
                    break
            if terminated or in_episode >= episode_steps:
                env.reset()
                cell, in_episode, episodes = base.cell, 0, episodes + 1
                s = score_of(cell)
                if s <= best_score:
                    best_score = s
                    if best.offer(steps, s, cell):
                        done = True
                        break
        if progress:
            progress(steps, best.elapsed())
    return finish("randomwalk", best, steps, budget, {"episodes": episodes})


def run_random(env, budget: Budget, seed: int, progress: Progress | None = None) -> RunResult:
    """Score uniformly random cells (with replacement); one step = one score evaluation.

    Args:
        env: a :class:`HandoverEnv` (its score source and grid are used).
        budget: time and/or step cap.
        seed: the run's seed (the cells are pre-drawn in blocks from one Generator).
        progress: called every :data:`BLOCK` steps.
    """
    base: HandoverEnv = env.unwrapped
    _, rng = seeds_of(seed)
    score, size = base.scores.score, base.grid.size
    best = BestSoFar(base.location, budget.stop_score, budget.stop_cells)
    step_limit, time_limit = budget.step_limit, budget.time_limit
    steps, best_score, done = 0, math.inf, False
    while not done and steps < step_limit and best.elapsed() < time_limit:
        for cell in rng.integers(size, size=int(min(BLOCK, step_limit - steps))).tolist():
            steps += 1
            s = score(cell)
            if s <= best_score:
                best_score = s
                if best.offer(steps, s, cell):
                    done = True
                    break
        if progress:
            progress(steps, best.elapsed())
    return finish("random", best, steps, budget)


def run_hillclimb(env, budget: Budget, seed: int, progress: Progress | None = None) -> RunResult:
    """Steepest ascent of the env's reward over the 6-neighbourhood, restarted at a random cell
    (the env's reset) at every local optimum or terminal cell.

    The reward (1/E² plus the symmetry term) rather than the bare score is climbed, so that a
    plateau of equal scores still has a direction (toward the midline) as it has for the
    learners. One step = one transition (a neighbour evaluated), so budgets compare with them.

    Args:
        env: a :class:`HandoverEnv` (possibly wrapped).
        budget: time and/or step cap.
        seed: the run's seed (the env's random starts).
        progress: called about every :data:`BLOCK` steps.
    """
    base: HandoverEnv = env.unwrapped
    env_seed, _ = seeds_of(seed)
    env.reset(seed=env_seed)
    transition, score_of = base.transition, base.scores.score
    best = BestSoFar(base.location, budget.stop_score, budget.stop_cells)
    step_limit, time_limit = budget.step_limit, budget.time_limit
    cell = base.cell
    here, best_score = base.reward(cell), score_of(cell)
    done = best.offer(0, best_score, cell)
    steps, restarts, next_check = 0, 0, BLOCK
    while not done and steps < step_limit:
        if steps >= next_check:
            next_check += BLOCK
            if progress:
                progress(steps, best.elapsed())
            if best.elapsed() >= time_limit:
                break
        move, move_reward, terminal, cut = cell, here, False, False
        for a in range(6):
            if steps >= step_limit:
                cut = True  # the cap cut the look short
                break
            nxt, s, r, terminated = transition(cell, a)
            steps += 1
            if s <= best_score:
                best_score = s
                if best.offer(steps, s, nxt):
                    done = True
                    break
            if r > move_reward:
                move, move_reward, terminal = nxt, r, terminated
        if cut:
            break  # no restart: it would score a cell beyond the cap
        if move == cell or terminal:
            env.reset()
            cell, restarts = base.cell, restarts + 1
            here, s = base.reward(cell), score_of(cell)
            if s <= best_score:
                best_score = s
                done = best.offer(steps, s, cell) or done
        else:
            cell, here = move, move_reward
    if progress:
        progress(steps, best.elapsed())
    return finish("hillclimb", best, steps, budget, {"restarts": restarts})


@dataclass(frozen=True)
class Exhaustive:
    """The ground truth of a landscape for one objective.

    Attributes:
        score: the lowest feasible score.
        cells: flat indices of every cell at it.
        location: the most symmetric of them (x, y, z) [m].
        fraction: share of the feasible cells at the minimum.
    """

    score: float
    cells: np.ndarray
    location: tuple[float, float, float]
    fraction: float


def exhaustive(landscape: Landscape, objective: str = "paper_postural") -> Exhaustive:
    """Read the landscape's minimum of ``objective`` (every cell was evaluated by the sweep)."""
    cells, best = optimum(landscape, objective)
    return Exhaustive(float(landscape.arrays[objective][cells[0]]), cells,
                      tuple(float(v) for v in best), len(cells) / int(landscape.feasible.sum()))
