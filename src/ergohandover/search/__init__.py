"""Searches for a worker's handover location, one protocol for all: the paper's tabular
Q-learner, DQN and SAC, walks through the grid, and ask/tell searchers (random order, the
population prior, Bayesian optimisation, TPE, CMA-ES, particle swarms), each named in one
registry, run by one :func:`run` within one :class:`Budget`, leaving one :class:`Record`."""

from .protocol import AskTellSearcher, Evaluations, Searcher, replay, run
from .record import Budget, Record
from .registry import SEARCHERS, entry, make

__all__ = ["SEARCHERS", "AskTellSearcher", "Budget", "Evaluations", "Record", "Searcher",
           "entry", "make", "replay", "run"]
