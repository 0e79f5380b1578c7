"""The recommendation of searchers without a model of their own: a Gaussian process over the
tried cells' answers, whose lowest posterior mean is recommended, never a lucky reading."""

from __future__ import annotations

import math

import numpy as np

from ergohandover.landscape.grid import Grid
from ergohandover.search import make
from ergohandover.search.surrogate import surrogate_recommendation
from ergohandover.twin.task import Boundary

GRID = Grid(Boundary((0.0, 0.14), (1.0, 1.14), (0.3, 0.44)), 0.01)  # 15 x 15 x 15 cells


def cell(i: int, j: int, k: int) -> int:
    return int(np.ravel_multi_index((i, j, k), GRID.shape))


def test_repeated_readings_are_averaged_so_one_lucky_low_reading_is_not_recommended():
    steady, lucky = cell(2, 2, 2), cell(12, 12, 12)
    cells = [steady, lucky, steady, lucky, steady, lucky, lucky]
    scores = [4.0, 5.0, 4.0, 5.0, 4.0, 5.0, 2.0]  # the lucky cell reads 2 once, 5 three times
    assert min(zip(scores, cells, strict=True))[1] == lucky  # what the lowest reading picks
    assert surrogate_recommendation(GRID, cells, scores) == steady


def test_a_low_reading_among_higher_neighbours_loses_to_a_low_plateau():
    spike = [cell(3, 7, 7), cell(4, 7, 7), cell(5, 7, 7), cell(4, 6, 7), cell(4, 8, 7)]
    plateau = [cell(11, 7, 7), cell(12, 7, 7), cell(11, 8, 7)]
    cells = [*spike, *plateau]
    scores = [6.0, 2.0, 6.0, 6.0, 6.0, 3.0, 3.0, 3.0]  # one 2 amid 6s; three 3s together
    assert surrogate_recommendation(GRID, cells, scores) in plateau


def test_exact_answers_on_a_smooth_bowl_recommend_the_lowest_and_never_an_untried_cell():
    rng = np.random.default_rng(3)
    cells = rng.choice(GRID.size, 20, replace=False)
    xyz = GRID.coordinates(cells)
    scores = 1 + 200 * ((xyz - GRID.coordinates([cell(7, 7, 7)])[0]) ** 2).sum(1)
    found = surrogate_recommendation(GRID, cells, scores)
    assert found == cells[int(np.argmin(scores))]


def test_infeasible_answers_carry_no_score_and_nothing_feasible_recommends_nothing():
    a, b = cell(0, 0, 0), cell(14, 14, 14)
    assert surrogate_recommendation(GRID, [a, b], [math.inf, math.inf]) is None
    assert surrogate_recommendation(GRID, [a, b], [math.inf, 7.0]) == b
    assert surrogate_recommendation(GRID, [], []) is None
    same = [cell(1, 1, 1), cell(9, 9, 9), cell(5, 5, 5)]
    assert surrogate_recommendation(GRID, same, [3.0, 3.0, 3.0]) == same[0]  # the first of equals


def test_a_searcher_without_a_model_recommends_through_it():
    searcher = make("random-order", GRID, 0)
    steady, lucky = cell(2, 2, 2), cell(12, 12, 12)
    neighbours = [cell(12, 12, 11), cell(12, 11, 12), cell(11, 12, 12), cell(12, 12, 13)]
    for c, score in [(steady, 3.0), (cell(2, 2, 3), 3.0), *[(n, 7.0) for n in neighbours],
                     (lucky, 2.0)]:
        searcher._pending = c  # these handovers, whatever it would have proposed
        searcher.tell(c, score)
    recommended = searcher.recommend()
    assert recommended.cell == steady and math.isnan(recommended.p_optimal)
