"""A recommendation from a model of the worker's scores, for searchers that have none of their
own.

Where a searcher only proposes cells (random order, the prior alone, CMA-ES, particle swarms,
Bayesian optimisation, a learner's walk), the location of its lowest single answer is a poor
recommendation once answers carry error: among ten noisy readings the lowest is as often a lucky
reading as a good location (the winner's curse). Here the answers heard so far are smoothed by a
Gaussian process over the cells' positions: nearby handovers inform each other, repeated
readings at a cell are averaged, and one low reading among higher neighbours is pulled up. The
recommendation is the tried cell of lowest posterior mean score: a cell never handed over at is
never recommended, because between tried cells the model only interpolates.

The process has a constant mean (the mean answer), a squared-exponential kernel whose variance
is the answers' variance, and Gaussian noise. Its length scale and noise are the pair of
:data:`LENGTHS_M` × :data:`NOISE_SDS` of largest marginal likelihood given the answers, so exact
answers are smoothed little and noisy ones more. Infeasible answers carry no score and are left
out. The model states no probability that its recommendation is the worker's optimum: it knows
nothing of the cells it was not told about.
"""

from __future__ import annotations

import numpy as np

from ..landscape.grid import Grid

LENGTHS_M = (0.01, 0.02, 0.04)
"""Length scales tried [m]: one to four of the study's 1 cm cells. A worker's optimum is often a
plateau of one or two cells beside higher ones; longer scales pull it up with its neighbours
(the personalisation part's in-model workers: fewer true optima recommended at 25 handovers)."""
NOISE_SDS = (0.05, 0.25, 0.5, 1.0, 2.0)
"""Noise SDs tried [score points]: from exact answers to a rater's error of two points."""
FLOOR = 0.25
"""The kernel's variance [score points²] when every answer so far is the same: a score point's
half-step, so a first difference can still move the recommendation."""


def surrogate_recommendation(grid: Grid, cells, scores) -> int | None:
    """The tried cell of lowest posterior mean score (the first tried of equals); None if no
    answer was feasible. ``cells`` and ``scores`` are the handovers in order (a cell may
    repeat; ``inf``: infeasible)."""
    cells = np.asarray(cells, dtype=int)
    y = np.asarray(scores, dtype=float)
    keep = np.isfinite(y)
    if not keep.any():
        return None
    cells, y = cells[keep], y[keep]
    found, first = np.unique(cells, return_index=True)
    tried = found[np.argsort(first)]  # in the order they were first tried
    if tried.size == 1:
        return int(tried[0])
    mean = posterior_mean(grid.coordinates(cells), y, grid.coordinates(tried))
    return int(tried[int(np.argmin(np.round(mean, 9)))])


def posterior_mean(x: np.ndarray, y: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The process's posterior mean at ``at`` (m, 3) given answers ``y`` (n,) at ``x`` (n, 3),
    under the length scale and noise of largest marginal likelihood; see the module."""
    centred = y - y.mean()
    signal = max(float(y.var()), FLOOR)
    d2 = ((x[:, None, :] - x[None, :, :]) ** 2).sum(-1)  # (n, n)
    lengths = np.asarray(LENGTHS_M)[:, None, None, None]
    noise = np.asarray(NOISE_SDS)[None, :, None, None] ** 2
    k = signal * np.exp(-d2 / (2 * lengths ** 2)) + noise * np.eye(len(y))  # (L, N, n, n)
    chol = np.linalg.cholesky(k)
    alpha = np.linalg.solve(k, np.broadcast_to(centred, k.shape[:-1])[..., None])[..., 0]
    fit = -0.5 * (centred * alpha).sum(-1) - np.log(np.diagonal(chol, axis1=-2,
                                                                 axis2=-1)).sum(-1)
    li, ni = np.unravel_index(int(np.argmax(fit)), fit.shape)
    cross = signal * np.exp(-((at[:, None, :] - x[None, :, :]) ** 2).sum(-1)
                            / (2 * LENGTHS_M[li] ** 2))  # (m, n)
    return y.mean() + cross @ alpha[li, ni]
