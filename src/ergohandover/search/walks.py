"""Walks through the environment on the learners' budget, without learning: a random walk (the
learner's moves and restarts), random draws (uniform, with replacement) and greedy hill-climbing
with random restarts. Each is run like a learner (:mod:`.env_agent`):
``run(env, budget, seed, config, progress) -> Record``."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..envs.handover_env import EPISODE_STEPS, HandoverEnv
from ..errors import ConfigError
from .qlearning import seeds_of
from .record import BLOCK, Budget, Progress, Record, Tracker


@dataclass(frozen=True)
class WalkConfig:
    """The random walk's one setting: steps after which an episode is cut and restarted at a
    random cell (the learners')."""

    episode_steps: int = EPISODE_STEPS

    def __post_init__(self):
        if self.episode_steps < 1:
            raise ConfigError(f"episode_steps = {self.episode_steps} is outside the valid range "
                              "(at least 1)")


def run_randomwalk(env, budget: Budget, seed: int, config: WalkConfig | None = None,
                   progress: Progress | None = None) -> Record:
    """Walk the grid with uniformly random actions: Q-learning's moves, episode ends and random
    restarts, without the learning (what the tabular learner does while its Q-table is flat).

    Args:
        env: a :class:`HandoverEnv` (possibly wrapped; its transition is used directly).
        budget: time and/or step cap (one step = one transition, as for the learners).
        seed: the run's seed (the env's starts and the agent's actions, as Q-learning's).
        config: its episode truncation (default: the learners').
        progress: called every :data:`BLOCK` steps.
    """
    episode_steps = (config or WalkConfig()).episode_steps
    base: HandoverEnv = env.unwrapped
    env_seed, rng = seeds_of(seed)
    env.reset(seed=env_seed)
    transition, score_of = base.transition, base.scores.score
    cell = base.cell
    best = Tracker.of(base.location, budget)
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
    return best.finish("randomwalk", steps, budget, {"episodes": episodes})


def run_random_draws(env, budget: Budget, seed: int, config: None = None,
                     progress: Progress | None = None) -> Record:
    """Score uniformly random cells, with replacement; one step = one score read (a repeat
    costs a step, unlike :mod:`.random_order`).

    Args:
        env: a :class:`HandoverEnv` (its score source and grid are used).
        budget: time and/or step cap.
        seed: the run's seed (the cells are pre-drawn in blocks from one Generator).
        config: none (the signature of every run).
        progress: called every :data:`BLOCK` steps.
    """
    base: HandoverEnv = env.unwrapped
    _, rng = seeds_of(seed)
    score, size = base.scores.score, base.grid.size
    best = Tracker.of(base.location, budget)
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
    return best.finish("random-draws", steps, budget)


def run_hillclimb(env, budget: Budget, seed: int, config: None = None,
                  progress: Progress | None = None) -> Record:
    """Steepest ascent of the env's reward over the 6-neighbourhood, restarted at a random cell
    (the env's reset) at every local optimum or terminal cell.

    The reward (1/E² plus the symmetry term) rather than the bare score is climbed, so that a
    plateau of equal scores still has a direction (toward the midline) as it has for the
    learners. One step = one transition (a neighbour evaluated), so budgets compare with them.

    Args:
        env: a :class:`HandoverEnv` (possibly wrapped).
        budget: time and/or step cap.
        seed: the run's seed (the env's random starts).
        config: none (the signature of every run).
        progress: called about every :data:`BLOCK` steps.
    """
    base: HandoverEnv = env.unwrapped
    env_seed, _ = seeds_of(seed)
    env.reset(seed=env_seed)
    transition, score_of = base.transition, base.scores.score
    best = Tracker.of(base.location, budget)
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
    return best.finish("hillclimb", steps, budget, {"restarts": restarts})
