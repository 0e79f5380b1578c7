"""The one protocol of a search for a handover location: a :class:`Searcher` is run against a
score source within a :class:`~.record.Budget` by :func:`run`, and leaves a
:class:`~.record.Record`.

Two kinds of searcher meet here (the registry, :mod:`.registry`, names them all):

- *ask/tell* searchers (:class:`AskTellSearcher`): they propose a cell, are told its score,
  and propose the next. Where every evaluation is a real handover with a person, a search
  must be driven from outside like this. A searcher is deterministic given its seed and the
  answers it was told, so its state is its history: :func:`replay` rebuilds it, which is how
  ``ergohandover personalise`` resumes.
- agents of the environment (the learners and walks, :mod:`.env_agent`), which move through
  the grid in their own loop: they count env *steps* (the learning study's unit), or, run
  against :class:`Evaluations`, distinct cells like any searcher.

The rule of a real handover lives in :class:`Evaluations`: a cell already scored is answered
from memory and costs nothing, and a searcher may read at most :data:`ASKS_PER_EVALUATION`
scores per evaluation of its budget, so one that keeps to known cells ends instead of looping.
A score is the objective at the cell (lower is better); ``math.inf`` says the worker could not
take the box there.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Iterable, Sequence
from contextlib import suppress
from typing import NamedTuple

from ..envs.scores import Answer, ScoreSource
from ..errors import ConfigError
from ..landscape.grid import Grid
from .preferences import PreferenceScores
from .prior import Prior
from .record import Budget, Progress, Record, Tracker

ASKS_PER_EVALUATION = 50
"""Scores a search may read per evaluation of its budget, repeats included: far above what any
searcher needs (an ask/tell searcher proposes new cells; a walk's step reaches a new cell about
half the time or more), so it ends only a search that keeps to known cells."""


class Recommendation(NamedTuple):
    """Where a searcher would hand over now: ``cell`` (None: nothing feasible seen yet) and
    its model's probability that the cell is the worker's optimum (NaN: a searcher without a
    model of the worker)."""

    cell: int | None
    p_optimal: float = math.nan


class Spent(Exception):
    """The budget is spent: raised through a searcher's loop by :class:`Evaluations` and
    caught by :func:`run` (never leaves it)."""


def finite_or_inf(score: float) -> float:
    """A score as a searcher takes it: NaN and infinities become ``inf`` (infeasible)."""
    return score if math.isfinite(score) else math.inf


def told(answer: Answer | float) -> Answer:
    """An answer as a searcher is told it: a bare score is an answer of a score alone; NaN and
    infinities become ``inf`` (infeasible)."""
    if isinstance(answer, Answer):
        return answer._replace(score=finite_or_inf(float(answer.score)))
    return Answer(finite_or_inf(float(answer)))


class Evaluations:
    """The answers a search pays for: each distinct cell once, a repeat from memory for free.

    Args:
        scores: where a new cell's answer comes from (the landscape, the twin, a person).
        budget: evaluations and/or seconds, optional stop score or cells (not steps).
        known: (cell, answer or score) pairs evaluated before this run (a resumed session's):
            answered from memory, and counted against the budget.
        progress: called after every new evaluation.
        recommend_at: after how many evaluations an ask/tell searcher's recommendation is
            kept (in :attr:`recommendations`, and the record's ``info``).
    """

    def __init__(self, scores: ScoreSource, budget: Budget,
                 known: Iterable[tuple[int, Answer | float]] = (),
                 progress: Progress | None = None, recommend_at: Iterable[int] = ()):
        if budget.steps is not None:
            raise ConfigError("evaluations are counted in evaluations, not steps")
        self.source, self.grid, self.budget = scores, scores.grid, budget
        self.limit = min(budget.evaluations or scores.grid.size, scores.grid.size)
        self.tracker = Tracker(scores.grid.point, budget.stop_score, budget.stop_cells)
        self.known: dict[int, Answer] = {}  # cell -> its answer, in the order evaluated
        self.asks, self.progress = 0, progress
        self.recommend_at = frozenset(int(n) for n in recommend_at)
        self.recommendations: dict[int, Recommendation] = {}  # handovers -> the searcher's
        for cell, answer in known:
            self._add(int(cell), told(answer))
        self.asks = len(self.known)

    @property
    def spent(self) -> int:
        """Distinct cells evaluated, earlier ones (``known``) included."""
        return len(self.known)

    @property
    def stopped_by(self) -> str | None:
        """Why no more may be evaluated (:attr:`Record.stopped_by`'s words), or None."""
        if self.tracker.reached:
            return "stop_score"
        if self.budget.evaluations is not None and self.spent >= self.budget.evaluations:
            return "evaluation_cap"
        if self.spent >= self.grid.size:
            return "grid"
        if self.asks >= ASKS_PER_EVALUATION * self.limit:
            return "ask_cap"
        if self.tracker.elapsed() >= self.budget.time_limit:
            return "time_cap"
        return None

    def answer(self, cell: int) -> Answer:
        """The answer at ``cell``: from memory if it was evaluated, else from the source (one
        evaluation); :class:`Spent` once the budget is."""
        if self.stopped_by:
            raise Spent
        self.asks += 1
        cell = int(cell)
        known = self.known.get(cell)
        if known is not None:
            return known
        answer = told(self.source.answer(cell))
        self._add(cell, answer)
        if self.progress:
            self.progress(self.spent, self.tracker.elapsed())
        return answer

    def score(self, cell: int) -> float:
        """The score at ``cell`` (:meth:`answer`'s), for searchers that hear scores alone."""
        return self.answer(cell).score

    def _add(self, cell: int, answer: Answer) -> None:
        self.known[cell] = answer
        if answer.score <= self.tracker.best:
            self.tracker.offer(self.spent, answer.score, cell)

    def record(self, searcher: str, info: dict | None = None) -> Record:
        return self.tracker.record(searcher, self.spent, self.stopped_by or "evaluation_cap",
                                   "evaluations", {"asks": self.asks, **(info or {})},
                                   cells=list(self.known),
                                   scores=[a.score for a in self.known.values()])


class Searcher(ABC):
    """Searches the cells of ``grid`` for the lowest score.

    Args:
        grid: the cells it may evaluate.
        seed: its only source of randomness.
        prior: where the worker's optimum is expected (a population prior), for searchers
            that take one; None: no prior.
    """

    name: str = ""
    answers: str = "scores"
    """What it is told: ``scores``, or ``preferences`` (:mod:`.pairwise`)."""
    unit: str = "evaluations"
    """What its budget counts when it is given a number without a unit (``train --steps``)."""

    def __init__(self, grid: Grid, seed: int, prior: Prior | None = None):
        self.grid, self.seed, self.prior = grid, int(seed), prior

    @abstractmethod
    def search(self, evaluations: Evaluations) -> dict:
        """Evaluate cells through ``evaluations`` until it raises :class:`Spent`; returns the
        searcher's own figures (for :attr:`Record.info`)."""

    def drive(self, scores: ScoreSource, budget: Budget, progress: Progress | None) -> Record:
        """A run counted in env steps (only agents of the environment have one)."""
        raise ConfigError(f"searcher {self.name!r} counts evaluations, not steps")


class AskTellSearcher(Searcher):
    """Proposes cells one at a time (:meth:`ask`) and learns from their answers
    (:meth:`tell`)."""

    @abstractmethod
    def ask(self) -> int:
        """The next flat cell to evaluate."""

    @abstractmethod
    def tell(self, cell: int, answer: Answer | float) -> None:
        """The answer observed at ``cell`` (:class:`~..envs.scores.Answer`: its score,
        ``math.inf`` where infeasible, and what came with it; a bare score is an answer of a
        score alone)."""

    def recommend(self) -> Recommendation:
        """Where it would hand over after what it was told, and its model's probability that
        this is the worker's optimum."""
        raise ConfigError(f"searcher {self.name!r} makes no recommendation")

    def search(self, evaluations: Evaluations) -> dict:
        while not evaluations.stopped_by:
            cell = int(self.ask())
            self.tell(cell, evaluations.answer(cell))
            if evaluations.spent in evaluations.recommend_at:
                evaluations.recommendations[evaluations.spent] = self.recommend()
        return {}


def run(searcher: Searcher, scores: ScoreSource, budget: Budget,
        progress: Progress | None = None,
        known: Sequence[tuple[int, Answer | float]] = (),
        recommend_at: Iterable[int] = ()) -> Record:
    """Run ``searcher`` against ``scores`` until ``budget`` is spent or its stop is reached.

    Args:
        searcher: from the registry (:func:`~.registry.make`).
        scores: the score at a cell: a landscape, the twin, a person (every source answers
            ``score(cell)``).
        budget: in evaluations (every searcher) or steps (agents of the environment only), and
            /or seconds.
        progress: called as ``progress(spent, elapsed_s)`` while it runs.
        known: (cell, answer or score) of an earlier session, already told to ``searcher``
            (:func:`replay`): answered from memory and counted in the budget.
        recommend_at: after how many evaluations an ask/tell searcher's recommendation
            (:class:`Recommendation`) is kept, in the record's ``info["recommendations"]``.
    """
    if budget.steps is not None or (budget.evaluations is None and searcher.unit == "steps"):
        return searcher.drive(scores, budget, progress)
    if searcher.answers != getattr(scores, "answers", "scores"):
        scores = told_as(searcher, scores, budget)
    evaluations = Evaluations(scores, budget, known, progress, recommend_at)
    info = {}
    with suppress(Spent):
        info = searcher.search(evaluations)
    if evaluations.recommend_at:
        info = {**info, "recommendations": evaluations.recommendations}
    return evaluations.record(searcher.name, info)


def told_as(searcher: Searcher, scores: ScoreSource, budget: Budget) -> ScoreSource:
    """``scores`` as a searcher told preferences hears them (:class:`~.pairwise.
    PreferenceScores`); a stop at a score means nothing to it."""
    if searcher.answers != "preferences":
        raise ConfigError(f"searcher {searcher.name!r} is told scores, and the answers are "
                          "preferences")
    if budget.stop_score is not None or budget.stop_cells is not None:
        raise ConfigError(f"searcher {searcher.name!r} is told preferences: it cannot stop at "
                          "a score (give it a budget of evaluations)")
    return PreferenceScores(scores)


def replay(searcher: AskTellSearcher,
           history: Sequence[tuple[int, Answer | float]]) -> AskTellSearcher:
    """Tell ``searcher`` an earlier session's answers in order (each with what it carried: a
    searcher that fits a twin hears the postures again), asking before each as that session
    did; a proposal that differs from the recorded one means the history is not this
    searcher's (another seed, searcher or grid) and is refused.

    A proposal of a cell already answered that is not the next entry of ``history`` is
    answered from memory, as :class:`Evaluations` did in that session.
    """
    known: dict[int, Answer] = {}
    for number, (cell, answer) in enumerate(history, start=1):
        cell, answer = int(cell), told(answer)
        proposed = searcher.ask()
        while proposed != cell and proposed in known:
            searcher.tell(proposed, known[proposed])
            proposed = searcher.ask()
        if proposed != cell:
            raise ConfigError(f"history trial {number}: cell {cell} was not proposed by "
                              f"searcher {searcher.name!r} with seed {searcher.seed} (it "
                              f"proposes {proposed}): the state file is not this session's")
        known[cell] = answer
        searcher.tell(cell, answer)
    return searcher
