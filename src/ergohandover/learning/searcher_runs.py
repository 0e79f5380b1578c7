"""An ask/tell searcher run as an agent of ``train`` and the benchmarks: the same budget, trace
and result as the learners, one step = one distinct evaluation (a repeat is free, as in
:func:`~.ask_tell.run_search`)."""

from __future__ import annotations

from .ask_tell import make_searcher, run_search
from .prior import Prior
from .trace import BestSoFar, Budget, Progress, RunResult, finish


def run_searcher(name: str, env, budget: Budget, seed: int, progress: Progress | None = None,
                 prior: Prior | None = None) -> RunResult:
    """Drive searcher ``name`` against ``env``'s score source until the budget is spent.

    Args:
        name: a searcher of :data:`~.ask_tell.SEARCHERS`.
        env: a :class:`~ergohandover.envs.HandoverEnv` (its grid and scores are used).
        budget: time and/or step cap (steps = distinct evaluations), optional stop score or
            cells.
        seed: the searcher's seed.
        progress: called after every evaluation.
        prior: the worker's prior (a warm start; the ``prior`` searcher needs one).
    """
    base = env.unwrapped
    best = BestSoFar(base.location, budget.stop_score, budget.stop_cells)
    searcher = make_searcher(name, base.grid, seed, prior)
    score, evaluations = base.scores.score, 0

    def score_of(cell: int) -> float:
        nonlocal evaluations
        evaluations += 1
        value = score(cell)
        if value <= best.best:
            best.offer(evaluations, value, cell)
        if progress:
            progress(evaluations, best.elapsed())
        return value

    limit = base.grid.size if budget.steps is None else min(budget.steps, base.grid.size)
    record = run_search(searcher, score_of, limit,
                        stop=lambda: best.reached or best.elapsed() >= budget.time_limit)
    return finish(name, best, len(record.cells), budget, {"asks": record.asks})
