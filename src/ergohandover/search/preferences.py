"""Answers that are preferences: which of the last two handovers was better.

Every handover after the first is compared with the last feasible one before it: the answer is
:data:`BETTER` (this one was better), :data:`WORSE` or :data:`SAME`, or ``inf`` where the worker
could not take the box. :class:`PreferenceScores` turns a score source's answers into such
comparisons (:mod:`.pairwise` is the searcher told them).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ..envs.scores import ScoreSource

BETTER, SAME, WORSE = -1.0, 0.0, 1.0
"""The answers comparing a handover with the one before it."""


def comparisons(answers: Sequence[float]) -> list[tuple[int, int, float]]:
    """(winner, loser, weight) pairs of the answers in order: each feasible answer compares its
    handover with the last feasible one before it; an infeasible one loses to that one."""
    pairs, last = [], None
    for i, answer in enumerate(answers):
        if not math.isfinite(answer):
            if last is not None:
                pairs.append((last, i, 1.0))
            continue
        if last is not None:
            if answer == BETTER:
                pairs.append((i, last, 1.0))
            elif answer == WORSE:
                pairs.append((last, i, 1.0))
            else:
                pairs += [(i, last, 0.5), (last, i, 0.5)]
        last = i
    return pairs


class PreferenceScores(ScoreSource):
    """A score source's answers as preferences: each feasible handover compared with the last
    feasible one before it (:data:`BETTER`, :data:`SAME`, :data:`WORSE`; the first: SAME),
    ``inf`` where the worker could not take the box. ``last_answer`` is the answer the source
    gave, for the record."""

    answers = "preferences"

    def __init__(self, scores: ScoreSource):
        self.source, self.grid, self.objective = scores, scores.grid, scores.objective
        self.last_answer: float | None = None
        self._previous: float | None = None

    def score(self, flat: int) -> float:
        answer = float(self.source.score(flat))
        self.last_answer = answer
        if not math.isfinite(answer):
            return math.inf
        previous, self._previous = self._previous, answer
        if previous is None or answer == previous:
            return SAME
        return BETTER if answer < previous else WORSE
