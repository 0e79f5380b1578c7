"""The propose → observe → update loop of a search for one worker's handover location.

Where every evaluation is a real handover with a person (on a site, in VR), a searcher must be
driven from outside: it *asks* for the next location to try, somebody observes the score there,
and it is *told* the answer. Every searcher of :data:`SEARCHERS` works that way, over the
flat cells of one :class:`~ergohandover.landscape.grid.Grid` (worker frame, metres).

A searcher is deterministic given its seed and the answers it was told, so its state is its
history: :func:`replay` rebuilds a searcher from the (cell, score) pairs of an interrupted
session, which is how ``ergohandover personalise`` resumes, and the study's runs are
reproducible from their seeds. The searchers of :mod:`.searchers` go further: they never ask for
a cell they have been told about (:class:`~.cells.NewCellSearcher`).

A score is the objective at the cell (lower is better); ``math.inf`` says the worker could not
take the box there (infeasible). A searcher may propose a cell it has already been told about;
the loop then reuses the known answer (:func:`run_search`), as a practitioner would, and counts
no new evaluation.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..errors import ConfigError
from ..landscape.grid import Grid
from .prior import Prior


class Searcher(ABC):
    """Proposes cells of ``grid`` one at a time and learns from their scores.

    Args:
        grid: the locations it may propose.
        seed: its only source of randomness.
        prior: where the worker's optimum is expected (a population prior), used as a warm
            start by searchers that take one; None: no prior.
    """

    name: str = ""

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None):
        self.grid, self.seed, self.prior = grid, int(seed), prior

    @abstractmethod
    def ask(self) -> int:
        """The next flat cell to evaluate."""

    @abstractmethod
    def tell(self, cell: int, score: float) -> None:
        """The score observed at ``cell`` (``math.inf``: infeasible)."""


class RandomSearcher(Searcher):
    """Uniformly random cells, without replacement (the practitioner's baseline)."""

    name = "random"

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None):
        super().__init__(grid, seed, prior)
        self._rng = np.random.default_rng(self.seed)
        self._told: set[int] = set()

    def ask(self) -> int:
        while True:  # a repeat is rare: grids have ~10^4-10^6 cells against <= 10^3 asks
            cell = int(self._rng.integers(self.grid.size))
            if cell not in self._told:
                return cell

    def tell(self, cell: int, score: float) -> None:
        self._told.add(int(cell))


SearcherFactory = Callable[[Grid, int, "Prior | None"], Searcher]
SEARCHERS: dict[str, SearcherFactory] = {"random": RandomSearcher}
"""Every ask/tell searcher by name (more register themselves in :mod:`.searchers`)."""


def make_searcher(name: str, grid: Grid, seed: int, prior: Prior | None = None) -> Searcher:
    """The searcher ``name`` over ``grid``; a one-line ConfigError for an unknown name."""
    if name not in SEARCHERS:
        from . import searchers  # noqa: F401  (registers the library-backed searchers)
    if name not in SEARCHERS:
        raise ConfigError(f"searcher = {name!r} is not allowed (use {', '.join(SEARCHERS)})")
    return SEARCHERS[name](grid, seed, prior)


def replay(searcher: Searcher, history: Sequence[tuple[int, float]]) -> Searcher:
    """Tell ``searcher`` an earlier session's answers in order, asking before each as that
    session did; a proposal that differs from the recorded one means the history is not this
    searcher's (another seed, searcher or grid) and is refused.

    ``history`` may list every answer (repeats included) or only the distinct evaluations (a
    :class:`SearchRecord`): a proposal of a cell already answered that is not the next entry
    is answered from memory, as :func:`run_search` did in that session.
    """
    known: dict[int, float] = {}
    for number, (cell, score) in enumerate(history, start=1):
        cell, score = int(cell), float(score)
        proposed = searcher.ask()
        while proposed != cell and proposed in known:
            searcher.tell(proposed, known[proposed])
            proposed = searcher.ask()
        if proposed != cell:
            raise ConfigError(f"history trial {number}: cell {cell} was not proposed by "
                              f"searcher {searcher.name!r} with seed {searcher.seed} (it "
                              f"proposes {proposed}): the state file is not this session's")
        known[cell] = score
        searcher.tell(cell, score)
    return searcher


@dataclass
class SearchRecord:
    """What one search saw, in order.

    Attributes:
        cells: every distinct cell evaluated, in order.
        scores: their scores (``inf``: infeasible).
        asks: proposals made (repeats of a known cell included).
    """

    cells: list[int] = field(default_factory=list)
    scores: list[float] = field(default_factory=list)
    asks: int = 0

    def evaluations_to(self, threshold: float) -> int | None:
        """How many evaluations until the first score at or below ``threshold``."""
        hits = np.flatnonzero(np.asarray(self.scores, dtype=float) <= threshold)
        return int(hits[0]) + 1 if hits.size else None

    @property
    def best(self) -> tuple[int, float] | None:
        """The first cell at the lowest score seen, and that score."""
        if not self.scores:
            return None
        i = int(np.argmin(self.scores))
        return self.cells[i], self.scores[i]


def run_search(searcher: Searcher, score_of: Callable[[int], float], budget: int,
               stop_at: float | None = None, max_asks: int | None = None,
               stop: Callable[[], bool] | None = None) -> SearchRecord:
    """Drive ``searcher`` against ``score_of`` for at most ``budget`` evaluations.

    Args:
        searcher: the searcher.
        score_of: the oracle (the twin's landscape in the study; a person in the field).
        budget: distinct evaluations allowed.
        stop_at: stop at the first score at or below it (the worker's known optimum, in the
            study: stopping there changes no evaluations-to-target); None runs the budget out.
        max_asks: proposals allowed in all, repeats included (default: 20 × ``budget``), so a
            searcher that keeps proposing known cells cannot loop forever.
        stop: asked before each proposal; True ends the search (a wall-clock cap).
    """
    if budget < 1:
        raise ConfigError(f"budget = {budget} is outside the valid range (at least 1)")
    record, known = SearchRecord(), {}
    max_asks = 20 * budget if max_asks is None else max_asks
    while len(record.cells) < budget and record.asks < max_asks and not (stop and stop()):
        cell = int(searcher.ask())
        record.asks += 1
        if cell in known:
            searcher.tell(cell, known[cell])
            continue
        score = float(score_of(cell))
        known[cell] = score
        record.cells.append(cell)
        record.scores.append(score)
        searcher.tell(cell, score)
        if stop_at is not None and score <= stop_at:
            break
    return record


def finite_or_inf(score: float) -> float:
    """A score as a searcher takes it: NaN and infinities become ``inf`` (infeasible)."""
    return score if math.isfinite(score) else math.inf
