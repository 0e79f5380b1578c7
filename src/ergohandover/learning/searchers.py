"""Registers the searchers beyond random sampling in :data:`~.ask_tell.SEARCHERS`.

Each entry imports its module when a searcher is made, so that naming the registry loads
neither Optuna nor torch (the GP sampler's).

- ``prior``: the population prior alone (:mod:`.prior_search`);
- ``bo``: Bayesian optimisation, Optuna's GPSampler (:mod:`.optuna_searchers`);
- ``tpe``: Optuna's TPESampler (:mod:`.optuna_searchers`);
- ``cmaes``: CMA-ES with restarts (:mod:`.cmaes_search`);
- ``pso``: particle-swarm optimisation (:mod:`.pso`).
"""

from __future__ import annotations

from importlib import import_module

from ..landscape.grid import Grid
from .ask_tell import SEARCHERS, Searcher, SearcherFactory
from .prior import Prior


def _lazy(module: str, cls: str) -> SearcherFactory:
    def make(grid: Grid, seed: int, prior: Prior | None = None) -> Searcher:
        return getattr(import_module(f".{module}", __package__), cls)(grid, seed, prior)

    return make


SEARCHERS.update({
    "prior": _lazy("prior_search", "PriorSearcher"),
    "bo": _lazy("optuna_searchers", "GPSearcher"),
    "tpe": _lazy("optuna_searchers", "TPESearcher"),
    "cmaes": _lazy("cmaes_search", "CMAESSearcher"),
    "pso": _lazy("pso", "PSOSearcher"),
})
