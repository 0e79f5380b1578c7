"""The fitted twin's proposal: one handover ahead, the cell whose answer is expected to leave
the recommendation most probable, checked against the posterior's own update."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from ergohandover.envs.scores import Answer
from ergohandover.landscape.grid import Grid
from ergohandover.landscape.store import landscape_of
from ergohandover.search import make
from ergohandover.search.fitted_twin import (
    FIELD_ANGLES,
    BodyPosterior,
    FittedTwinSearcher,
    TwinLibrary,
)
from ergohandover.search.lookahead import CELLS, most_telling
from ergohandover.search.prior import Prior
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary

# 2 cm cells, so that every candidate is also displaced up and forward by a cell.
GRID = Grid(Boundary((-0.02, 0.02), (0.95, 1.25), (0.36, 0.48)), 0.02)
BODIES = [BodySpec.from_percentile(p) for p in ("p50-male", "p95-male")]
EVALUATORS = [Evaluator(body=b) for b in BODIES]
PRIOR = Prior((0.0, 1.1, 0.42), (0.05, 0.05, 0.05), (0.0, 0.5, 0.3))
WORKER = ((BODIES[0].stature_m + BODIES[1].stature_m) / 2, "male")


def library() -> TwinLibrary:
    return TwinLibrary(GRID, EVALUATORS, lambda i: landscape_of(EVALUATORS[i], GRID,
                                                                progress=False),
                       "paper_postural", ["p50-male", "p95-male"], worker=WORKER,
                       angle_sd_deg=3.0)


def hypothesis_answer(posterior: BodyPosterior, k: int, d: int, cell: int) -> Answer:
    """What hypothesis (candidate k, displacement d) answers at ``cell``: its angles there."""
    source, inside = posterior.sources(cell)
    angles = posterior.library.angles([int(source[d])], [k])[0, 0]
    if not inside[d] or np.isnan(angles).all():
        return Answer(math.inf, "infeasible")
    score = float(posterior.library.values(k)[source[d]])
    return Answer(score, "posture", posture=dict(zip(FIELD_ANGLES, map(float, angles),
                                                     strict=True)))


def expected_best(posterior: BodyPosterior, cell: int) -> float:
    """Brute force: each hypothesis taken as the truth, the posterior updated with its answer
    at ``cell``, the highest probability any cell then has of being the optimum, averaged
    over the hypotheses' weights."""
    weights = posterior.weights
    total = 0.0
    for k, d in zip(*np.nonzero(weights > 0), strict=True):
        after = copy.deepcopy(posterior)
        after.update(cell, hypothesis_answer(posterior, int(k), int(d), cell))
        total += weights[k, d] * after.p_optimal().max()
    return total / weights[weights > 0].sum()


@pytest.fixture(scope="module")
def told():
    """A posterior after one handover at the most probable optimum, the cells it would choose
    among and the answer it heard."""
    searcher = make("fitted-twin", GRID, 0, PRIOR, twins=library())
    first = searcher.ask()
    answer = hypothesis_answer(searcher.posterior, 1, 0, first)
    searcher.tell(first, answer)
    untried = [int(c) for c in searcher._ranked() if int(c) != first][:CELLS]
    return searcher, untried, answer


def test_the_proposal_is_the_cell_the_posteriors_own_update_expects_to_teach_most(told):
    searcher, untried, answer = told
    posterior = searcher.posterior
    assert np.count_nonzero(posterior.weights) > 2  # displaced hypotheses too
    worth = np.array([expected_best(posterior, c) for c in untried])
    chosen = most_telling(posterior, np.array(untried), answer)
    assert worth[untried.index(chosen)] == pytest.approx(worth.max(), abs=1e-9)
    assert searcher.ask() == chosen
    # Here the most probable optimum untried (the greedy proposal) is worth less.
    assert worth[0] < worth.max() - 1e-6


def test_the_first_handover_is_the_most_probable_optimum_and_greedy_stays_available():
    looking = make("fitted-twin", GRID, 0, PRIOR, twins=library())
    greedy = FittedTwinSearcher(GRID, 0, PRIOR, twins=library(), lookahead=False)
    first = looking.ask()
    assert first == greedy.ask() == int(looking._ranked()[0])  # nothing heard: the prior's
    for searcher in (looking, greedy):
        searcher.tell(first, hypothesis_answer(searcher.posterior, 1, 0, first))
    assert greedy.ask() == next(int(c) for c in greedy._ranked() if int(c) != first)
    assert looking.ask() not in looking.told
