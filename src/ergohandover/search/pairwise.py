"""Preferences instead of scores: a searcher told only which of the last two handovers was
better.

A worker, or whoever watches, often cannot give a reliable number, but can say which of two
handovers felt better. Here every handover after the first is compared with the one before it
(the last feasible one): the answer is :data:`BETTER` (this one was better), :data:`WORSE` or
:data:`SAME`, or ``inf`` when the worker could not take the box. A score source answers so
through :class:`PreferenceScores` (the lower of the two answers it would have given is
preferred, so a preference is flipped exactly as often as the scores' own error reverses their
order: more often the closer the two scores are; equal answers are :data:`SAME`), and a person
answers so in ``ergohandover personalise --answers pairwise``.

:class:`PairwiseSearcher` keeps a Gaussian-process model of how good each location is, fitted
to the comparisons by Laplace's approximation of the probit preference likelihood (Chu and
Ghahramani, ICML 2005): P(a preferred to b) = Φ((f(a) − f(b)) / (√2 σ)), an answer
:data:`SAME` counting as half a preference each way, and a handover the worker could not take
as one the handover before it is preferred to. It proposes by Thompson sampling (as CoSpar,
Tucker et al. ICRA 2020): one draw of the model over candidate cells — drawn around the
worker's prior and around the most preferred location so far — and the best of the draw, never
a cell twice. Its recommendation is the location it has seen with the highest posterior mean
(:func:`preferred`). The kernel's length scale and the preference noise are fixed
(:data:`LENGTH_M`, :data:`NOISE`), not fitted: a few comparisons cannot fit them; they were
chosen among six pairs on population workers outside the personalisation study's
(``experiments/tools/tune_pairwise.py``).

BoTorch's ``PairwiseGP`` with EUBO, the field's library for this, is
:class:`~.pairwise_botorch.BotorchPairwiseSearcher` (``pairwise-botorch``; the ``preferences``
extra). Side by side on the personalisation study's in-model workers, from their priors, paired
by worker and seed (``python experiments/tools/compare_pairwise.py``; differences BoTorch −
this, mean over workers, 95 % bootstrap over workers):

- with BoTorch's default kernel fitted to the comparisons, it is worse everywhere (20 workers,
  1 run each per answer model): mean true regret +0.80 (+0.50 to +1.10) and +1.10 (+0.75 to
  +1.45) points after 10 and 25 handovers with exact answers, +0.75 (+0.20 to +1.40) and +1.05
  (+0.65 to +1.45) with postures measured with 5° of error, +1.10 (+0.60 to +1.55) and +0.60
  (+0.25 to +1.00) with a rater of ICC 0.51; at a true optimum 55 (35 to 75) and 70 (50 to 90)
  points less often with exact answers; worse than no search in 35-85 % of runs (this one:
  5-40 %); ~20 s a run of 25 handovers against 0.5 s;
- with this module's fixed kernel (``pairwise-botorch``'s default) the two cannot be told apart
  (30 workers, 2 runs each per answer model: ``--workers 30 --runs 2 --searchers pairwise
  botorch-fixed``): regret −0.02 (−0.12 to +0.08) and +0.00 (−0.10 to +0.10) with exact
  answers, −0.10 (−0.37 to +0.15) and +0.02 (−0.18 to +0.22) at 5°, +0.07 (−0.07 to +0.22) and
  +0.02 (−0.15 to +0.18) with the rater; at a true optimum +2 (−10 to +12), 0 (−10 to +10), 0
  (−13 to +13), 0 (−8 to +8), −7 (−18 to +3) and +2 (−13 to +17) points. Every interval holds
  0 and the point estimates fall either side; this searcher needs no optional dependency and
  made the study's committed results, so the study keeps it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy.special import log_ndtr

from ..landscape.grid import Grid
from .cells import NewCellSearcher, prior_point
from .preferences import BETTER, SAME, WORSE, PreferenceScores, comparisons
from .prior import Prior
from .protocol import Recommendation

__all__ = ["BETTER", "SAME", "WORSE", "PairwiseSearcher", "PreferenceModel", "PreferenceScores",
           "comparisons", "model_of", "most_preferred", "preferred"]

LENGTH_M = 0.03
"""The kernel's length scale [m]: how far apart two locations still feel alike."""
NOISE = 1.0
"""σ of the probit preference likelihood, in units of the model's prior SD (1)."""
CANDIDATES = 128
"""Candidate cells drawn around the prior and around the most preferred location each."""
NEWTON_STEPS = 30


def kernel(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Squared-exponential covariance of points (n, 3) and (m, 3) [m]."""
    d2 = ((a[:, None, :] - b[None, :, :]) ** 2).sum(axis=2)
    return np.exp(-d2 / (2 * LENGTH_M ** 2))


def square_root(cov: np.ndarray) -> np.ndarray:
    """The symmetric square root S (S @ S = cov) of a covariance (m, m), its negative
    eigenvalues (rounding) taken as 0: a draw ``mean + S @ z`` (z standard normal) has that
    covariance.

    Not ``vectors * sqrt(values)``: an eigenvector's sign (and its basis within equal
    eigenvalues) is LAPACK's arbitrary choice, and which it returns can change with the last
    bit of the covariance, and so with the processor's numerical code paths (AVX2 or AVX-512
    kernels of the same libraries). ``S`` is the same whichever basis LAPACK returns, so a run
    depends on its seed alone.
    """
    values, vectors = np.linalg.eigh((cov + cov.T) / 2)
    return (vectors * np.sqrt(np.clip(values, 0, None))) @ vectors.T


class PreferenceModel:
    """The Laplace posterior of the goodness f at ``points`` given the ``pairs``; see the
    module."""

    def __init__(self, points: np.ndarray, pairs: list[tuple[int, int, float]]):
        self.points = np.asarray(points, float)
        n = len(self.points)
        self.K = kernel(self.points, self.points) + 1e-6 * np.eye(n)
        winners = np.array([p[0] for p in pairs], dtype=int)
        losers = np.array([p[1] for p in pairs], dtype=int)
        weights = np.array([p[2] for p in pairs], dtype=float)
        scale = math.sqrt(2) * NOISE
        f = np.zeros(n)
        D = np.zeros((len(pairs), n))  # each pair's (winner - loser) difference operator
        D[np.arange(len(pairs)), winners] = 1.0
        D[np.arange(len(pairs)), losers] -= 1.0
        for _ in range(NEWTON_STEPS):
            z = D @ f / scale
            ratio = np.exp(-0.5 * z ** 2 - 0.5 * math.log(2 * math.pi) - log_ndtr(z))
            grad = D.T @ (weights * ratio) / scale
            W = D.T @ (D * (weights * ratio * (z + ratio))[:, None]) / scale ** 2
            new = self.K @ np.linalg.solve(np.eye(n) + W @ self.K, W @ f + grad)
            if np.abs(new - f).max() < 1e-8:
                f = new
                break
            f = new
        self.f, self.W = f, W if pairs else np.zeros((n, n))
        self.alpha = np.linalg.solve(self.K, f)

    def posterior(self, at: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Mean (m,) and covariance (m, m) of f at points ``at`` (m, 3)."""
        Ks = kernel(self.points, at)
        mean = Ks.T @ self.alpha
        n = len(self.points)
        cov = kernel(at, at) - Ks.T @ self.W @ np.linalg.solve(np.eye(n) + self.K @ self.W, Ks)
        return mean, cov


def model_of(grid: Grid, cells: Sequence[int],
             answers: Sequence[float]) -> PreferenceModel | None:
    """The preference model of the answers at ``cells`` (None before any comparison)."""
    pairs = comparisons(answers)
    return PreferenceModel(grid.coordinates(list(cells)), pairs) if pairs else None


def most_preferred(model: PreferenceModel | None, answers: Sequence[float]) -> int | None:
    """The index of the feasible handover with the highest posterior mean goodness under
    ``model`` (the first of equals); the first feasible one without a model; None if none was
    feasible."""
    feasible = [i for i, a in enumerate(answers) if math.isfinite(a)]
    if not feasible:
        return None
    if model is None:
        return feasible[0]
    return feasible[int(np.argmax(model.f[feasible]))]


def preferred(grid: Grid, cells: Sequence[int], answers: Sequence[float]) -> int | None:
    """The index (into ``cells``) of the handover the model of the answers prefers
    (:func:`most_preferred`)."""
    return most_preferred(model_of(grid, cells, answers), answers)


class PairwiseSearcher(NewCellSearcher):
    """Thompson sampling from a preference GP; see the module."""

    name = "pairwise"
    answers = "preferences"

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None):
        super().__init__(grid, seed, prior)
        self._rng = np.random.default_rng(self.seed)
        if prior is None:
            self._centre, self._sd = (self.shape - 1) / 2, self.shape / 4
        else:
            self._centre, self._sd = prior_point(grid, prior)
            self._sd = np.maximum(self._sd, 1.0)

    def recommend(self) -> Recommendation:
        """The location its model prefers among those tried (:func:`preferred`); its
        probability of being the best of them is :meth:`confidence`'s."""
        best = preferred(self.grid, self.cells, self.told_answers)
        return Recommendation(None if best is None else self.cells[best])

    def confidence(self, draws: int = 4000) -> float | None:
        """The model's probability that :meth:`recommend`'s location is the best of the
        feasible ones seen (Monte Carlo over its posterior, seeded); None before any
        comparison."""
        answers = self.told_answers
        feasible = [i for i, a in enumerate(answers) if math.isfinite(a)]
        model = model_of(self.grid, self.cells, answers)
        if model is None or not feasible:
            return None
        mean, cov = model.posterior(self.grid.coordinates([self.cells[i] for i in feasible]))
        noise = np.random.default_rng(self.seed).standard_normal((draws, len(feasible)))
        samples = mean + noise @ square_root(cov)  # symmetric: each row is S @ its noise
        best = feasible.index(most_preferred(model, answers))
        return float((samples.argmax(axis=1) == best).mean())

    def candidates(self, best: int | None) -> np.ndarray:
        """The candidate cells of a proposal, sorted: :data:`CANDIDATES` drawn around the
        prior and as many around ``best`` (the most preferred cell; None: the prior again),
        those already told left out."""
        around = self._centre if best is None else self.index(best)
        points = np.concatenate([
            self._rng.normal(self._centre, self._sd, (CANDIDATES, 3)),
            self._rng.normal(around, np.maximum(self._sd / 2, 1.0), (CANDIDATES, 3))])
        index = np.clip(np.rint(points), 0, self.shape - 1).astype(int)
        cells = np.unique(np.ravel_multi_index(tuple(index.T), self.grid.shape))
        return np.array([c for c in cells.tolist() if c not in self.told], dtype=int)

    def _propose(self) -> int:
        if not self.told:
            first = (self.snap(self._centre) if self.prior is not None
                     else int(self._rng.integers(self.grid.size)))
            return first
        told, answers = self.cells, self.told_answers
        model = model_of(self.grid, told, answers)  # one fit serves the choice and the draw
        best = most_preferred(model, answers)
        cells = self.candidates(None if best is None else told[best])
        if cells.size == 0:
            return self.nearest_new(self.index(told[-1]))
        if model is None:
            return int(self._rng.choice(cells))
        mean, cov = model.posterior(self.grid.coordinates(cells))
        draw = mean + square_root(cov) @ self._rng.standard_normal(len(cells))
        return int(cells[int(np.argmax(draw))])

    def _learn(self, cell: int, score: float) -> None:
        """Nothing to update: the model is fitted to everything told at the next proposal."""
