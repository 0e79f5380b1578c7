"""The pairwise searcher on BoTorch: PairwiseGP's posterior mean ranks what was preferred, one
lucky comparison does not outweigh consistent ones, and runs are seeded and replayable."""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch
from test_pairwise import GRID, OPTIMUM, PRIOR, bowl

from ergohandover.envs.scores import ArrayScores
from ergohandover.search import Budget, make, replay, run
from ergohandover.search.pairwise_botorch import BotorchPairwiseSearcher
from ergohandover.search.preferences import BETTER, SAME, WORSE


def told(cells: list[int], answers: list[float], fit: bool) -> BotorchPairwiseSearcher:
    """A searcher that was told ``answers`` at ``cells`` (set directly: these cells are not
    its own proposals)."""
    searcher = BotorchPairwiseSearcher(GRID, 0, PRIOR, fit=fit)
    searcher.told.update(zip(cells, answers, strict=True))
    return searcher


@pytest.mark.parametrize("fit", [False, True])
def test_comparisons_consistently_preferring_one_location_make_it_the_recommendation(fit):
    far = [GRID.nearest_cell(p) for p in ([-0.2, 0.9, 0.25], [0.2, 1.35, 0.3],
                                          [-0.25, 1.3, 0.55], [0.25, 0.85, 0.5])]
    target = GRID.nearest_cell(OPTIMUM)
    # The target beats the first; each later one loses to the one before it.
    cells, answers = [far[0], target, *far[1:]], [SAME, BETTER, WORSE, WORSE, WORSE]
    searcher = told(cells, answers, fit)
    mean = searcher.model().mean(cells)
    assert int(np.argmax(mean)) == 1
    assert searcher.recommend().cell == target
    assert 0 < searcher.confidence(draws=500) <= 1


@pytest.mark.parametrize("fit", [False, True])
def test_one_lucky_comparison_does_not_outweigh_consistent_ones(fit):
    lucky = np.array([-0.2, 0.9, 0.3])
    good = [GRID.nearest_cell(OPTIMUM + d) for d in ([0, 0, 0], [0.02, 0, 0], [0, 0.02, 0])]
    bad = [GRID.nearest_cell(lucky + d) for d in ([0.02, 0, 0], [0, 0.02, 0], [0, 0, 0.02],
                                                  [-0.02, 0, 0])]
    # The locations around the optimum beat those around ``lucky`` three times; ``lucky``
    # itself once beats the last of them (a lucky answer), then beats its own neighbour.
    cells = [bad[0], good[0], bad[1], good[1], bad[2], good[2],
             GRID.nearest_cell(lucky), bad[3]]
    answers = [SAME, BETTER, WORSE, BETTER, WORSE, BETTER, BETTER, WORSE]
    assert told(cells, answers, fit).recommend().cell in good


def test_infeasible_handovers_lose_to_the_last_feasible_one():
    a, b, c = (GRID.nearest_cell(OPTIMUM + d) for d in ([0, 0, 0], [0.1, 0, 0], [-0.1, 0, 0]))
    searcher = told([a, b], [math.inf, math.inf], fit=False)
    assert searcher.model() is None and searcher.recommend().cell is None
    # b could not be taken: it loses to a; c lost to a too.
    searcher = told([a, b, c], [SAME, math.inf, WORSE], fit=False)
    mean = searcher.model().mean([a, b, c])
    assert mean[0] > max(mean[1:]) and searcher.recommend().cell == a


def test_a_run_is_seeded_new_cells_replayable_and_leaves_torchs_generator_alone():
    values = bowl()
    values[GRID.coordinates(np.arange(GRID.size))[:, 0] < -0.1] = math.inf  # cannot be taken
    before = torch.get_rng_state()
    record = run(make("pairwise-botorch+prior", GRID, 3, PRIOR), ArrayScores(GRID, values),
                 Budget(evaluations=8), recommend_at=[8])
    assert torch.equal(torch.get_rng_state(), before)
    assert len(set(record.cells)) == 8
    assert set(record.scores) <= {BETTER, SAME, WORSE, math.inf}
    again = run(make("pairwise-botorch+prior", GRID, 3, PRIOR), ArrayScores(GRID, values),
                Budget(evaluations=8), recommend_at=[8])
    assert again.cells == record.cells
    best = record.info["recommendations"][8].cell
    assert best == again.info["recommendations"][8].cell and math.isfinite(values[best])
    searcher = replay(make("pairwise-botorch+prior", GRID, 3, PRIOR),
                      list(zip(record.cells[:6], record.scores[:6], strict=True)))
    assert searcher.ask() == record.cells[6]
    other = run(make("pairwise-botorch+prior", GRID, 4, PRIOR), ArrayScores(GRID, values),
                Budget(evaluations=8))
    assert other.cells[0] == record.cells[0] and other.cells != record.cells  # the seed's


def test_a_fitted_kernel_is_seeded_too():
    values = bowl()
    found = []
    for _ in range(2):
        searcher = BotorchPairwiseSearcher(GRID, 5, PRIOR, fit=True)
        record = run(searcher, ArrayScores(GRID, values), Budget(evaluations=5),
                     recommend_at=[5])
        found.append((record.cells, record.info["recommendations"][5].cell))
        assert searcher.fits == 4  # one model an answer after the first
    assert found[0] == found[1]


def test_told_preferences_it_moves_towards_the_bowls_minimum():
    values = bowl()
    record = run(make("pairwise-botorch+prior", GRID, 1, PRIOR), ArrayScores(GRID, values),
                 Budget(evaluations=12), recommend_at=[1, 12])
    first, last = (record.info["recommendations"][n].cell for n in (1, 12))
    assert values[last] < values[first]
