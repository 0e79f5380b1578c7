"""Which handover teaches the fitted twin most about where the worker's optimum lies.

Handing the box over where the optimum is most probable (the greedy proposal) keeps asking
about cells whose hypotheses already agree: near the optimum, two bodies whose optima are a
cell apart take the box with nearly the same angles. What decides the recommendation is
whether the hypotheses that put the optimum at one cell can be told from those that put it at
the next, and a handover can do that only where their angles (or scores) differ by more than
the instrument's error.

:func:`most_telling` looks one handover ahead: for each untried cell among the most probable
optima and each of the heaviest hypotheses taken as the truth, the answer that hypothesis
would give there reweighs the others, and the cell is worth the expected highest probability
any cell then has of being the optimum (a knowledge gradient on the probability of a correct
recommendation). The answer is taken at its expectation, the hypothesis's own angles: under
Gaussian error the expected log-likelihood ratio of two hypotheses is the plug-in's, so the
ranking of cells is the same and no draw is needed (a proposal is deterministic, and a
resumed session proposes what it would have).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..envs.scores import Answer

if TYPE_CHECKING:
    from .fitted_twin import BodyPosterior

HYPOTHESES = 48
"""The heaviest hypotheses the lookahead weighs (the posterior's tail beyond them moves the
recommendation little and costs the most to weigh)."""
CELLS = 12
"""The untried cells of highest probability of being the optimum it chooses among."""


def most_telling(posterior: BodyPosterior, cells: np.ndarray, last: Answer) -> int:
    """The cell among ``cells`` (untried, most probable optimum first) whose answer is
    expected to leave the recommendation most probable; equal: the first.

    Args:
        posterior: the worker's posterior.
        cells: candidate flat cells, most probable first (the first :data:`CELLS` are
            weighed).
        last: the last answer heard: its kind (angles, and which of them its instrument sees;
            or a score alone) is the kind the next is expected to be.
    """
    from .fitted_twin import FEASIBILITY_MISS, FIELD_ANGLES, SCORE_SD

    cells = np.asarray(cells[:CELLS], dtype=np.intp)
    weights = posterior.weights.ravel()
    heaviest = np.argsort(weights)[::-1][:HYPOTHESES]
    heaviest = heaviest[weights[heaviest] > 0]
    if len(cells) < 2 or len(heaviest) < 2:
        return int(cells[0])
    prior = weights[heaviest] / weights[heaviest].sum()
    candidate, shift = np.unravel_index(heaviest, posterior.log_weight.shape)
    posture = last.posture or {}
    measured = np.array([posture.get(a, math.nan) for a in FIELD_ANGLES], float)
    seen = np.isfinite(measured) if math.isfinite(last.score) else np.zeros(0, bool)
    # (C, H, n): what each hypothesis would answer at each cell, whitened by the error it is
    # read with, so that squared distances are the log-likelihood's.
    where = [posterior.sources(int(c)) for c in cells]
    sources = np.stack([s[shift] for s, _ in where])  # (C, H) the candidates' cells
    inside = np.stack([i[shift] for _, i in where])
    if seen.any():
        answers = np.full((len(cells), len(heaviest), int(seen.sum())), np.nan)
        for k in np.unique(candidate):
            rows = candidate == k
            found = posterior.library.angles(sources[:, rows].ravel(), [int(k)])[0]
            answers[:, rows] = found[:, seen].reshape(len(cells), int(rows.sum()), -1)
        feasible = inside & ~np.isnan(answers).all(axis=2)
        root = np.linalg.cholesky(posterior.covariance[np.ix_(seen, seen)])
        answers = np.linalg.solve(root, np.nan_to_num(answers)[..., None])[..., 0]
    else:
        values = np.stack([posterior.library.values(int(k))[sources[:, i]]
                           for i, k in enumerate(candidate)], axis=1)  # (C, H)
        feasible = inside & np.isfinite(values)
        answers = (np.where(feasible, values, 0.0) / SCORE_SD)[..., None]
    gap = ((answers[:, :, None, :] - answers[:, None, :, :]) ** 2).sum(axis=3)  # (C, T, H)
    both = feasible[:, :, None] & feasible[:, None, :]
    neither = ~feasible[:, :, None] & ~feasible[:, None, :]
    fit = np.where(both, -0.5 * gap, np.where(neither, 0.0, FEASIBILITY_MISS))
    log_after = np.log(prior)[None, None, :] + fit
    after = np.exp(log_after - log_after.max(axis=2, keepdims=True))
    after /= after.sum(axis=2, keepdims=True)
    member, _ = optimum_membership(posterior, candidate, shift)  # (H, U)
    best = (after @ member).max(axis=2)  # (C, T): the recommendation's probability after
    return int(cells[int(np.argmax(best @ prior))])


def optimum_membership(posterior: BodyPosterior, candidate: np.ndarray, shift: np.ndarray
                       ) -> tuple[np.ndarray, np.ndarray]:
    """(H, U) whether each hypothesis's optimum holds each of the U cells any of them holds,
    and (U,) those flat cells."""
    shape = posterior.shape
    owners, found = [], []
    for h, (k, d) in enumerate(zip(candidate, shift, strict=True)):
        index = np.array(np.unravel_index(posterior.library.optimum(int(k)), tuple(shape))).T
        moved = index + posterior.shifts[int(d)]
        moved = moved[((moved >= 0) & (moved < shape)).all(axis=1)]
        found.append(np.ravel_multi_index(tuple(moved.T), tuple(shape)))
        owners.append(np.full(len(moved), h))
    flat = np.concatenate(found)
    cells, column = np.unique(flat, return_inverse=True)
    member = np.zeros((len(candidate), len(cells)))
    member[np.concatenate(owners), column] = 1.0
    return member, cells
