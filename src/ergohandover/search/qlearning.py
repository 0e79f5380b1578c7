"""Tabular Q-learning with Boltzmann (softmax) action selection, as Amani & Akhavian ran it.

Q(s, a) <- Q(s, a) + α (r + γ max_a' Q(s', a') − Q(s, a)), Q initialised to 0, α 0.1, γ 0.9,
actions drawn with probability ∝ exp(Q(s, a) / τ). Episodes start at a uniformly random cell
and end when the env terminates (score at most the target) or after ``episode_steps``; the run
keeps the lowest score seen and where, until its time or step cap.

The inner loop is plain Python over floats: the 6-way softmax with ``math.exp``, uniform random
numbers pre-drawn in blocks from the agent's own Generator, the Q-table a flat ``array('d')``
indexed ``6 * cell + action`` (8 bytes per entry, no per-state objects: 150 MB for the paper's
3.3 M-cell grid) and the env's own :meth:`HandoverEnv.transition` called directly.
"""

from __future__ import annotations

import math
from array import array
from dataclasses import dataclass

import numpy as np

from ..envs.handover_env import EPISODE_STEPS, HandoverEnv
from ..errors import ConfigError
from .record import BLOCK, Budget, Progress, Record, Tracker

TEMPERATURES = ("fixed", "adaptive")


@dataclass(frozen=True)
class QLearningConfig:
    """Hyperparameters; defaults are the paper's (text and published code).

    Args:
        alpha: learning rate (paper: 0.1).
        gamma: discount (paper: 0.9).
        temperature: ``fixed`` (τ stays ``tau``: what the published code does) or ``adaptive``
            (the paper's text: τ −= ``tau_step`` each time the score improves to below
            ``threshold``, τ += ``tau_step`` each time it worsens, kept within ``tau_bounds``).
        tau: (initial) Boltzmann temperature (paper: 0.7).
        tau_step: adaptive change of τ per event (paper: 0.1).
        tau_bounds: (lowest, highest) adaptive τ; the paper gives none: 0.1 keeps the softmax
            from collapsing to greedy on rewards of ~0.02-0.1, 2.0 keeps it from drifting to
            uniform forever (where the score rarely drops below ``threshold``, τ mostly
            rises and reaches 2.0 within a few thousand steps).
        threshold: the score below which an improvement lowers τ (paper: 5).
        episode_steps: steps after which an episode is cut and restarted at a random cell.
    """

    alpha: float = 0.1
    gamma: float = 0.9
    temperature: str = "fixed"
    tau: float = 0.7
    tau_step: float = 0.1
    tau_bounds: tuple[float, float] = (0.1, 2.0)
    threshold: float = 5.0
    episode_steps: int = EPISODE_STEPS

    def __post_init__(self):
        if self.temperature not in TEMPERATURES:
            raise ConfigError(f"temperature = {self.temperature!r} is not allowed (use "
                             f"{' or '.join(TEMPERATURES)})")
        for name, value, lo, hi in (("alpha", self.alpha, 0.0, 1.0),
                                    ("gamma", self.gamma, 0.0, 1.0)):
            if not lo < value <= hi:
                raise ConfigError(f"{name} = {value!r} is outside the valid range ({lo:g}, {hi:g}]")
        lo, hi = self.tau_bounds
        if not 0 < lo <= self.tau <= hi:
            raise ConfigError(f"tau = {self.tau!r} is outside the valid range {lo:g}-{hi:g}")
        if self.episode_steps < 1:
            raise ConfigError(f"episode_steps = {self.episode_steps} is outside the valid range "
                             "(at least 1)")


def adapt_temperature(tau: float, old: float, new: float, config: QLearningConfig) -> float:
    """The paper's adaptive temperature after a step from score ``old`` to ``new``.

    τ rises by ``tau_step`` when the score worsens (an infeasible cell, ``inf``, is worse than
    any score) and falls by it when the score improves to below ``threshold``; it stays within
    ``tau_bounds``.
    """
    if new > old:
        return min(tau + config.tau_step, config.tau_bounds[1])
    if new < old and new < config.threshold:
        return max(tau - config.tau_step, config.tau_bounds[0])
    return tau


def seeds_of(seed: int) -> tuple[int, np.random.Generator]:
    """One seed for the env's starts and one Generator for the agent's own draws."""
    env_seq, agent_seq = np.random.SeedSequence(seed).spawn(2)
    return int(env_seq.generate_state(1)[0]), np.random.default_rng(agent_seq)


_SPARE: dict[int, array] = {}
"""A zeroed Q-table per size, kept between runs in this process: allocating and zeroing the
paper grid's 150 MB table would otherwise cost a short run more than its steps."""


def zeroed_table(length: int) -> array:
    """A Q-table of ``length`` zeros, the spare one of a previous run if there is one (a run
    that fails never gives its table back, so a table in use is never handed out twice)."""
    spare = _SPARE.pop(length, None)
    return spare if spare is not None else array("d", [0.0]) * length


def run_qlearning(env, budget: Budget, seed: int, config: QLearningConfig | None = None,
                  progress: Progress | None = None) -> Record:
    """Learn on ``env`` until the budget is spent; keep the lowest score seen.

    Args:
        env: a :class:`HandoverEnv` (possibly wrapped; its transition is used directly).
        budget: time and/or step cap.
        seed: the run's seed; with a step cap the run is deterministic (trace, Q-table).
        config: hyperparameters (default: the paper's).
        progress: called every :data:`BLOCK` steps.

    Returns:
        The result, with the visited part of the Q-table in ``q_table``.
    """
    cfg = config or QLearningConfig()
    base: HandoverEnv = env.unwrapped
    env_seed, rng = seeds_of(seed)
    env.reset(seed=env_seed)
    cell = base.cell
    score = base.scores.score(cell)
    best = Tracker.of(base.location, budget)
    done = best.offer(0, score, cell)
    size = base.grid.size
    q = zeroed_table(6 * size)
    visited = bytearray(size)
    transition, exp = base.transition, math.exp
    alpha, gamma = cfg.alpha, cfg.gamma
    adaptive, tau = cfg.temperature == "adaptive", cfg.tau
    k = 1.0 / tau
    episode_steps, episodes, in_episode = cfg.episode_steps, 1, 0
    step_limit, time_limit = budget.step_limit, budget.time_limit
    steps, best_score = 0, best.best
    while not done and steps < step_limit and best.elapsed() < time_limit:
        draws = rng.random(int(min(BLOCK, step_limit - steps))).tolist()
        for u in draws:
            b = 6 * cell
            q0, q1, q2, q3, q4, q5 = q[b:b + 6]
            m = max(q0, q1, q2, q3, q4, q5)
            e0, e1, e2 = exp((q0 - m) * k), exp((q1 - m) * k), exp((q2 - m) * k)
            e3, e4, e5 = exp((q3 - m) * k), exp((q4 - m) * k), exp((q5 - m) * k)
            t = u * (e0 + e1 + e2 + e3 + e4 + e5)  # inverse-CDF draw from the softmax
            if t < e0:
                a = 0
            elif t < e0 + e1:
                a = 1
            elif t < e0 + e1 + e2:
                a = 2
            elif t < e0 + e1 + e2 + e3:
                a = 3
            elif t < e0 + e1 + e2 + e3 + e4:
                a = 4
            else:
                a = 5
            nxt, new, r, terminated = transition(cell, a)
            if terminated:
                target = r
            else:
                n = 6 * nxt
                target = r + gamma * max(q[n:n + 6])
            q[b + a] += alpha * (target - q[b + a])
            visited[cell] = 1
            steps += 1
            if new <= best_score:
                best_score = new
                if best.offer(steps, new, nxt):
                    done = True
                    break
            if adaptive:
                tau = adapt_temperature(tau, score, new, cfg)
                k = 1.0 / tau
            in_episode += 1
            if terminated or in_episode >= episode_steps:
                env.reset()
                cell, in_episode, episodes = base.cell, 0, episodes + 1
                score = base.scores.score(cell)
                if score <= best_score:
                    best_score = score
                    if best.offer(steps, score, cell):
                        done = True
                        break
            else:
                cell, score = nxt, new
        if progress:
            progress(steps, best.elapsed())
    best.stop()
    states = np.flatnonzero(np.frombuffer(visited, dtype=np.uint8))
    table = np.frombuffer(q, dtype=np.float64).reshape(size, 6)
    values = table[states].copy()
    table[states] = 0.0  # only visited states' rows are ever written: the table is zero again
    del table
    _SPARE[len(q)] = q
    info = {"episodes": episodes, "final_temperature": round(tau, 6),
            "visited_states": len(states)}
    return best.finish("qlearning", steps, budget, info, q_table=(states, values))
