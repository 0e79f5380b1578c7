"""The pairwise-preference searcher on BoTorch: ``PairwiseGP`` and EUBO.

The same searcher as :class:`~.pairwise.PairwiseSearcher` — told only which of the last two
handovers was better (:data:`~.preferences.BETTER`, :data:`~.preferences.WORSE`,
:data:`~.preferences.SAME`, or ``inf`` where the worker could not take the box), starting at the
worker's prior, choosing among the same candidate cells (drawn around the prior and around the
most preferred location, never a cell twice) — with the model and the choice from BoTorch, the
field's library for preference learning:

- the model is ``botorch.models.PairwiseGP`` (Laplace's approximation of the probit preference
  likelihood, Chu and Ghahramani 2005) on the cells' coordinates scaled to the grid's unit cube.
  By default (``fit=False``) its kernel is the hand-written searcher's, fixed: squared
  exponential of length scale :data:`~.pairwise.LENGTH_M` on every axis, output scale 1 (the
  probit noise is BoTorch's, 1, as the hand-written :data:`~.pairwise.NOISE`). With ``fit=True``
  it is BoTorch's default (RBF with a length scale per axis under a Gamma prior, an output scale
  under a box prior), fitted after every answer by maximising
  ``PairwiseLaplaceMarginalLogLikelihood``; a fit that fails (about 1 % of them) keeps that
  kernel at its priors' modes. Fitted, it recommended worse locations in every setting measured
  (a few comparisons flatten the evidence: the fit stretches the length scale or shrinks the
  output scale) and took 20 times as long (~30 s a run of 25 handovers), so the fixed kernel
  is the default (numbers: :mod:`.pairwise`);
- the comparisons are :func:`~.preferences.comparisons`'s: a handover the worker could not take
  loses to the last feasible one before it. ``PairwiseGP`` takes no weights, so an answer
  :data:`SAME` is both comparisons at full weight (the hand-written model counts each at half):
  a tie pulls the two locations' goodness together, twice as firmly;
- the next cell maximises the analytic Expected Utility of the Best Option (EUBO, Lin et al.
  AISTATS 2022: ``AnalyticExpectedUtilityOfBestOption``) of the pair it will be compared in —
  the candidate and the last feasible handover (``previous_winner``): E[max(f(x), f(last))];
- its recommendation is the feasible location tried with the highest posterior mean goodness
  (never the lowest reading), and :meth:`confidence` is the posterior's probability that it is
  the best of them.

Everything random is seeded from the run's seed: the candidates by the searcher's generator,
the fit (whose retries may draw from the priors) and the confidence's draws by a torch seed of
(seed, answers told) under ``torch.random.fork_rng``, so the global torch generator is left as
it was. BoTorch is imported when a model is first made (the ``preferences`` extra), so
``import ergohandover`` stays light.

Which of the two searchers finds the better location is measured by
``experiments/tools/compare_pairwise.py`` (its numbers: :mod:`.pairwise`).
"""

from __future__ import annotations

import math
import warnings
from typing import TYPE_CHECKING

import numpy as np

from ..landscape.grid import Grid
from .pairwise import LENGTH_M, PairwiseSearcher
from .preferences import comparisons
from .prior import Prior
from .protocol import Recommendation

if TYPE_CHECKING:
    import torch

__all__ = ["BotorchPairwiseSearcher", "PairwiseModel"]


class PairwiseModel:
    """A fitted ``PairwiseGP`` of the answers at ``cells`` (flat cells of ``grid``).

    Args:
        grid: the cells' grid (its bounds scale the coordinates to the unit cube).
        cells: the cells told, in order.
        answers: what was told about them (preferences, ``inf``: infeasible).
        fit: fit the kernel's hyperparameters (BoTorch's default kernel), else the
            hand-written searcher's fixed kernel.
        seed: the torch seed of the fit.

    ``fitted`` says whether the fit succeeded (where it fails, the default kernel is kept at
    its priors' modes).
    """

    def __init__(self, grid: Grid, cells: list[int], answers: list[float], fit: bool, seed: int):
        import torch
        from botorch.models import PairwiseGP

        self.grid = grid
        pairs = comparisons(answers)
        x = self.unit(cells)
        rows = [(winner, loser) for winner, loser, _ in pairs]
        with torch.random.fork_rng(), warnings.catch_warnings():
            # The fit's retries and numerical notes (jitter added, a retry from the priors)
            # are BoTorch's own handling; the searcher proceeds with what it returns.
            warnings.simplefilter("ignore")
            torch.manual_seed(seed)
            compared = torch.tensor(rows, dtype=torch.long)
            self.model = PairwiseGP(x, compared,
                                    covar_module=None if fit else fixed_kernel(grid))
            self.fitted = False
            if fit:
                from botorch.exceptions.errors import ModelFittingError
                from botorch.fit import fit_gpytorch_mll
                from botorch.models.pairwise_gp import PairwiseLaplaceMarginalLogLikelihood

                try:
                    fit_gpytorch_mll(PairwiseLaplaceMarginalLogLikelihood(
                        self.model.likelihood, self.model))
                    self.fitted = True
                except ModelFittingError:
                    # Every attempt stopped abnormally (a few comparisons often leave the
                    # evidence flat): BoTorch's default kernel at its priors' modes, unfitted,
                    # made afresh so that its Laplace fit matches those hyperparameters.
                    self.model = PairwiseGP(x, compared)
        self.model.eval()

    def unit(self, cells) -> torch.Tensor:
        """The cells' coordinates (n, 3) in the grid's unit cube, float64."""
        import torch

        lower, upper = bounds(self.grid)
        return torch.as_tensor((self.grid.coordinates(list(cells)) - lower) / (upper - lower),
                               dtype=torch.float64)

    def mean(self, cells) -> np.ndarray:
        """The posterior mean goodness at ``cells``."""
        import torch

        with torch.no_grad():
            return self.model.posterior(self.unit(cells)).mean.squeeze(-1).numpy()

    def eubo(self, cells, last: int) -> np.ndarray:
        """EUBO of comparing each of ``cells`` with the cell ``last``."""
        import torch
        from botorch.acquisition.preference import AnalyticExpectedUtilityOfBestOption

        acquisition = AnalyticExpectedUtilityOfBestOption(pref_model=self.model,
                                                          previous_winner=self.unit([last]))
        with torch.no_grad():
            return acquisition(self.unit(cells).unsqueeze(-2)).numpy()

    def p_best(self, cells, best: int, draws: int, seed: int) -> float:
        """The posterior probability that ``cells[best]`` is the best of ``cells`` (``draws``
        joint draws, seeded)."""
        import torch

        with torch.no_grad(), torch.random.fork_rng():
            torch.manual_seed(seed)
            samples = self.model.posterior(self.unit(cells)).rsample(torch.Size([draws]))
        return float((samples.squeeze(-1).argmax(dim=-1) == best).double().mean())


def bounds(grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    """The grid's lower and upper corner [m] (its first and last cell's coordinates)."""
    corners = grid.coordinates([0, grid.size - 1])
    return corners[0], corners[1]


def fixed_kernel(grid: Grid):
    """The hand-written searcher's kernel in unit-cube coordinates: squared exponential of
    length scale :data:`~.pairwise.LENGTH_M` [m] on every axis, output scale 1, not fitted."""
    import torch
    from gpytorch.kernels import RBFKernel, ScaleKernel

    lower, upper = bounds(grid)
    kernel = ScaleKernel(RBFKernel(ard_num_dims=3, dtype=torch.float64), dtype=torch.float64)
    kernel.base_kernel.lengthscale = torch.as_tensor(LENGTH_M / (upper - lower),
                                                     dtype=torch.float64)
    kernel.outputscale = torch.tensor(1.0, dtype=torch.float64)
    for parameter in kernel.parameters():
        parameter.requires_grad_(False)
    return kernel


class BotorchPairwiseSearcher(PairwiseSearcher):
    """EUBO over a BoTorch ``PairwiseGP``; see the module.

    Args:
        grid, seed, prior: as every searcher's.
        fit: fit the kernel to the comparisons (BoTorch's default kernel), or keep the
            hand-written searcher's fixed kernel (the default: fitted, it did worse).
    """

    name = "pairwise-botorch"
    answers = "preferences"

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None, fit: bool = False):
        super().__init__(grid, seed, prior)
        self.fit = fit
        self._model: tuple[int, PairwiseModel | None] | None = None  # (answers told, model)
        self.fits = self.failed_fits = 0  # models fitted, and those whose fit failed

    def model(self) -> PairwiseModel | None:
        """The model of everything told (None before any comparison): fitted once per answer,
        shared by the recommendation and the next proposal."""
        told = len(self.told)
        if self._model is None or self._model[0] != told:
            answers = self.told_answers
            made = None
            if comparisons(answers):
                made = PairwiseModel(self.grid, self.cells, answers, self.fit,
                                     self.torch_seed(told))
            self._model = (told, made)
            self.fits += made is not None and self.fit
            self.failed_fits += made is not None and self.fit and not made.fitted
        return self._model[1]

    def torch_seed(self, *stream: int) -> int:
        """The torch seed of the run's seed and a stream (the answers told, and what for)."""
        return int(np.random.SeedSequence([self.seed, *stream]).generate_state(1)[0])

    def best(self) -> int | None:
        """The index of the feasible handover with the highest posterior mean (the first of
        equals); the first feasible one without a model; None if none was feasible."""
        feasible = [i for i, a in enumerate(self.told_answers) if math.isfinite(a)]
        model = self.model()
        if not feasible or model is None:
            return feasible[0] if feasible else None
        cells = self.cells
        return feasible[int(np.argmax(model.mean([cells[i] for i in feasible])))]

    def recommend(self) -> Recommendation:
        """The tried location of highest posterior mean (:meth:`best`); its probability of
        being the best of them is :meth:`confidence`'s."""
        best = self.best()
        return Recommendation(None if best is None else self.cells[best])

    def confidence(self, draws: int = 4000) -> float | None:
        """The posterior's probability that :meth:`recommend`'s location is the best of the
        feasible ones seen; None before any comparison."""
        model, best = self.model(), self.best()
        if model is None or best is None:
            return None
        feasible = [c for c, a in self.told.items() if math.isfinite(a)]
        return model.p_best(feasible, feasible.index(self.cells[best]), draws,
                            self.torch_seed(len(self.told), 1))

    def _propose(self) -> int:
        if not self.told:
            return (self.snap(self._centre) if self.prior is not None
                    else int(self._rng.integers(self.grid.size)))
        told = self.cells
        best = self.best()
        cells = self.candidates(None if best is None else told[best])
        if cells.size == 0:
            return self.nearest_new(self.index(told[-1]))
        model = self.model()
        if model is None:
            return int(self._rng.choice(cells))
        # The next answer compares the new handover with the last feasible one.
        last = next(c for c, a in reversed(self.told.items()) if math.isfinite(a))
        return int(cells[int(np.argmax(model.eubo(cells, last)))])
