"""What a learned policy gives beyond search: greedy rollouts from random starts.

A learner's final Q-table (or network) is a policy: from any start, follow the best action. If
learning worked, that policy walks to the optimum in about as many steps as the start is far
from it; a random walk from the same starts mostly does not. Each walker moves with the env's
own :meth:`~ergohandover.envs.HandoverEnv.transition`, so the moves are those of training.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..envs.handover_env import HandoverEnv

Policy = Callable[[np.ndarray, np.random.Generator], np.ndarray]
"""``policy(cells, rng) -> actions``: an action (0-5) for each flat cell."""


@dataclass(frozen=True)
class Rollouts:
    """Greedy walks from ``starts``.

    Attributes:
        starts: (n,) flat start cells.
        reached: (n,) True where the walk reached a target cell within the step limit.
        steps: (n,) steps to the first target cell (0 at a start on it; -1 if not reached).
    """

    starts: np.ndarray
    reached: np.ndarray
    steps: np.ndarray

    @property
    def fraction(self) -> float:
        return float(self.reached.mean())

    @property
    def mean_steps(self) -> float:
        """Mean steps of the walks that reached the target (NaN if none did)."""
        return float(self.steps[self.reached].mean()) if self.reached.any() else float("nan")


def step_limit(env: HandoverEnv) -> int:
    """The grid's Manhattan diameter: a walk that heads for the target needs at most this."""
    return int(sum(n - 1 for n in env.grid.shape))


def roll_out(env: HandoverEnv, policy: Policy, mask: np.ndarray, starts: np.ndarray,
             limit: int, rng: np.random.Generator) -> Rollouts:
    """Walk every start with ``policy`` until it is on a target cell or ``limit`` steps pass.

    Args:
        env: the env (its transition moves the walkers).
        policy: the actions of the walkers still walking, all at once.
        mask: (grid.size,) True at target cells.
        starts: (n,) flat start cells.
        limit: steps per walk.
        rng: breaks ties between equal actions (and draws the random walk's).
    """
    base = env.unwrapped
    cells = np.asarray(starts, dtype=np.int64).copy()
    reached = mask[cells].copy()
    steps = np.where(reached, 0, -1)
    for t in range(1, limit + 1):
        walking = np.flatnonzero(~reached)
        if walking.size == 0:
            break
        actions = policy(cells[walking], rng)
        cells[walking] = [base.transition(c, a)[0]
                          for c, a in zip(cells[walking].tolist(), actions.tolist(), strict=True)]
        arrived = walking[mask[cells[walking]]]
        reached[arrived], steps[arrived] = True, t
    return Rollouts(np.asarray(starts), reached, steps)


def random_policy(cells: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """The random walk: a uniformly random action."""
    return rng.integers(6, size=len(cells))


def table_policy(q_table: tuple[np.ndarray, np.ndarray], size: int) -> Policy:
    """The greedy policy of a tabular learner's (visited states, Q-values (n, 6)).

    Ties (an unvisited state's six zeros above all) are broken uniformly at random: a fixed
    choice would send every walker in an unlearned region along the same axis.
    """
    states, values = q_table
    row = np.full(size, -1, dtype=np.int64)
    row[states] = np.arange(len(states))
    table = np.vstack([values, np.zeros((1, 6))])  # the last row: an unvisited state

    def policy(cells: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        q = table[row[cells]]
        best = q == q.max(axis=1, keepdims=True)
        return np.argmax(rng.random(q.shape) * best, axis=1)

    return policy


def network_policy(model, env: HandoverEnv) -> Policy:
    """The greedy policy of a trained SB3 DQN on ``env``'s position observation."""
    import torch

    base = env.unwrapped

    def policy(cells: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        obs = np.stack([base.observe(int(c)) for c in cells])
        with torch.no_grad():
            q = model.q_net(torch.as_tensor(obs, dtype=torch.float32))
        return q.argmax(dim=1).numpy()

    return policy
