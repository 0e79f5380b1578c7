"""The pairwise searcher: told only which of the last two handovers was better."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ergohandover.envs.scores import ArrayScores
from ergohandover.errors import ConfigError
from ergohandover.landscape.grid import Grid
from ergohandover.search import Budget, make, replay, run
from ergohandover.search.pairwise import (
    BETTER,
    SAME,
    WORSE,
    PreferenceModel,
    PreferenceScores,
    comparisons,
    preferred,
)
from ergohandover.search.prior import Prior
from ergohandover.twin.task import Boundary

GRID = Grid(Boundary((-0.3, 0.3), (0.8, 1.4), (0.2, 0.6)), 0.02)
OPTIMUM = np.array([0.06, 1.14, 0.44])
PRIOR = Prior((0.0, 1.1, 0.4), (0.04, 0.04, 0.04))


def bowl() -> np.ndarray:
    """Whole scores rising with the distance from OPTIMUM: one cell at the minimum."""
    points = GRID.coordinates(np.arange(GRID.size))
    return np.floor(3 + 8 * np.linalg.norm(points - OPTIMUM, axis=1) / 0.1)


def test_answers_become_comparisons_with_the_last_feasible_handover():
    answers = [SAME, BETTER, math.inf, WORSE, SAME]
    assert comparisons(answers) == [(1, 0, 1.0), (1, 2, 1.0), (1, 3, 1.0),
                                    (4, 3, 0.5), (3, 4, 0.5)]
    source = PreferenceScores(ArrayScores(GRID, bowl()))
    far, near, nearer = (GRID.nearest_cell(OPTIMUM + d) for d in
                         (np.array([0.2, 0, 0]), np.array([0.06, 0, 0]), np.zeros(3)))
    assert [source.score(c) for c in (far, near, near, nearer)] == [SAME, BETTER, SAME, BETTER]


def test_the_model_prefers_what_was_preferred():
    points = GRID.coordinates([0, 500, 1000, 1500])
    # 1 beat 0, 2 beat 1, 3 lost to 2: 2 is best, 0 worst.
    model = PreferenceModel(points, comparisons([SAME, BETTER, BETTER, WORSE]))
    assert int(np.argmax(model.f)) == 2 and int(np.argmin(model.f)) == 0
    mean, cov = model.posterior(points)
    assert np.allclose(mean, model.f, atol=1e-3)
    assert (np.diag(cov) > 0).all() and (np.diag(cov) < 1).all()
    assert preferred(GRID, [0, 500, 1000, 1500], [SAME, BETTER, BETTER, WORSE]) == 2
    assert preferred(GRID, [0, 500], [math.inf, SAME]) == 1  # nothing compared: the first
    assert preferred(GRID, [0], [math.inf]) is None


def test_told_preferences_it_finds_the_bowls_minimum_sooner_than_random_order():
    values = bowl()
    found = {}
    for name in ("pairwise+prior", "random-order"):
        regrets = []
        for seed in range(10):  # enough runs that the two means are not a tie
            record = run(make(name, GRID, seed, PRIOR), ArrayScores(GRID, values),
                         Budget(evaluations=25))
            if name.startswith("pairwise"):
                assert set(record.scores) <= {BETTER, SAME, WORSE, math.inf}
                best = preferred(GRID, record.cells, record.scores)
            else:
                best = int(np.argmin(record.scores))
            regrets.append(values[record.cells[best]] - values.min())
        found[name] = np.mean(regrets)
    assert found["pairwise+prior"] < found["random-order"] / 2


def test_proposals_are_new_cells_seeded_and_replayed():
    values = bowl()
    record = run(make("pairwise+prior", GRID, 3, PRIOR), ArrayScores(GRID, values),
                 Budget(evaluations=15))
    assert len(set(record.cells)) == 15
    again = run(make("pairwise+prior", GRID, 3, PRIOR), ArrayScores(GRID, values),
                Budget(evaluations=15))
    assert again.cells == record.cells
    searcher = replay(make("pairwise+prior", GRID, 3, PRIOR),
                      list(zip(record.cells[:10], record.scores[:10], strict=True)))
    assert searcher.ask() == record.cells[10]
    assert searcher.recommend().cell == record.cells[preferred(GRID, record.cells[:10],
                                                          record.scores[:10])]


def test_proposals_do_not_depend_on_the_eigenvectors_signs_lapack_returns(monkeypatch):
    # An eigenvector's sign is LAPACK's arbitrary choice and changes with the last bit of the
    # covariance (an AVX2 and an AVX-512 machine's BLAS kernels differ there): a run's
    # proposals, recommendation and confidence must be the same for every valid choice.
    def searched():
        searcher = make("pairwise+prior", GRID, 3, PRIOR)
        record = run(searcher, ArrayScores(GRID, bowl()), Budget(evaluations=12))
        return record.cells, searcher.recommend().cell, searcher.confidence(draws=500)

    as_returned = searched()
    eigh = np.linalg.eigh

    def flipped(a):  # the same decomposition, every other eigenvector negated
        values, vectors = eigh(a)
        return values, vectors * np.where(np.arange(len(values)) % 2, -1.0, 1.0)

    monkeypatch.setattr(np.linalg, "eigh", flipped)
    assert searched() == as_returned


def test_a_preference_searcher_cannot_stop_at_a_score():
    with pytest.raises(ConfigError, match="cannot stop at a score"):
        run(make("pairwise", GRID, 0), ArrayScores(GRID, bowl()),
            Budget(evaluations=10, stop_score=3.0))


def test_a_learner_given_the_prior_starts_every_episode_at_the_priors_cell():
    values = bowl()
    start = GRID.nearest_cell(PRIOR.location)
    for name in ("qlearning+prior", "randomwalk+prior"):
        record = run(make(name, GRID, 4, PRIOR), ArrayScores(GRID, values),
                     Budget(evaluations=40))
        assert record.cells[0] == start
        plain = run(make(name.removesuffix("+prior"), GRID, 4), ArrayScores(GRID, values),
                    Budget(evaluations=40))
        assert plain.cells[0] != start  # a random start without it
    with pytest.raises(ConfigError, match="needs a worker's prior"):
        make("qlearning+prior", GRID, 0)
