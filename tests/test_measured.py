"""Measured answers: the twin's posture at a handover, read with the robustness part's
measurement error and scored. Without error they are the twin's scores; with it they are the
robustness part's distribution, one draw per handover."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from ergohandover.envs import OnlineScores
from ergohandover.ergonomics import Posture
from ergohandover.errors import ConfigError
from ergohandover.landscape.grid import Grid
from ergohandover.robustness.posture_error import ErrorModel, monte_carlo
from ergohandover.search import Budget, make, run
from ergohandover.search.measured import MeasuredScores
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary

GRID = Grid(Boundary((-0.1, 0.1), (1.0, 1.2), (0.35, 0.5)), 0.05)  # 5 x 5 x 4 cells
EVALUATOR = Evaluator()


def measured(sd: float, seed: int = 0, objective: str = "paper_postural") -> MeasuredScores:
    return MeasuredScores(GRID, EVALUATOR, objective, ErrorModel(sd),
                          np.random.default_rng(seed), block=5)


@pytest.mark.parametrize("objective", ["paper_postural", "reba", "rula"])
def test_without_error_the_answers_are_the_twins_scores(objective):
    twin = OnlineScores(GRID, EVALUATOR, objective, block=5)
    source = measured(0.0, objective=objective)
    answers = [source.score(c) for c in range(GRID.size)]
    assert answers == [twin.score(c) for c in range(GRID.size)]
    assert source.measurements == GRID.size


def test_each_handover_is_a_new_measurement_and_a_seed_fixes_them():
    cell = next(c for c in range(GRID.size) if measured(0.0).posture(c) is not None)
    first, again = measured(10.0, seed=3), measured(10.0, seed=3)
    reads = [first.score(cell) for _ in range(40)]
    assert reads == [again.score(cell) for _ in range(40)]  # the seed fixes them
    assert len(set(reads)) > 1  # two handovers at one cell: two measurements
    other = measured(10.0, seed=4)
    assert [other.score(cell) for _ in range(40)] != reads  # another seed, other errors


def test_the_answers_follow_the_robustness_parts_distribution():
    cell = next(c for c in range(GRID.size) if measured(0.0).posture(c) is not None)
    source = measured(5.0, seed=1)
    reads = np.array([source.score(cell) for _ in range(3_000)])
    posture = Posture({k: np.array([v]) for k, v in source.posture(cell).items()})
    expected = monte_carlo(posture, ErrorModel(5.0), 20_000, np.random.default_rng(2),
                           settings=EVALUATOR.scoring)
    se = expected.sd["paper_postural"][0] / math.sqrt(len(reads))
    assert abs(reads.mean() - expected.mean["paper_postural"][0]) < 5 * se + 1e-9


def test_infeasible_cells_are_answered_as_such_and_a_search_runs_on_measurements():
    source = measured(5.0, seed=0)
    record = run(make("random-order", GRID, 0), source, Budget(evaluations=30))
    assert record.steps == 30 and source.measurements == 30
    twin = OnlineScores(GRID, EVALUATOR, "paper_postural", block=5)
    for cell, score in zip(record.cells, record.scores, strict=True):
        assert math.isinf(score) == math.isinf(twin.score(cell))


def test_bad_settings_are_refused():
    with pytest.raises(ConfigError, match="objective = 'lexicographic' is not allowed"):
        MeasuredScores(GRID, EVALUATOR, "lexicographic", ErrorModel(5.0),
                       np.random.default_rng(0))
    with pytest.raises(ConfigError, match="block = 0"):
        MeasuredScores(GRID, EVALUATOR, "reba", ErrorModel(5.0), np.random.default_rng(0), 0)


def test_the_recommendation_is_the_first_lowest_measured_score_within_the_budget():
    from ergohandover.study.measured_answers import recommendation

    scores = [math.inf, 7.0, 5.0, 6.0, 5.0, 4.0]
    assert recommendation(scores, 2) == 1
    assert recommendation(scores, 5) == 2  # the first of equals
    assert recommendation(scores, 6) == 5
    assert recommendation([math.inf, math.inf], 2) is None


def measured_job(sd: float, searcher: str = "cmaes+prior"):
    from ergohandover.search.prior import Prior
    from ergohandover.study.measured_answers import MeasuredJob

    return MeasuredJob("w1", EVALUATOR, GRID, "paper_postural", searcher, sd, (3, 10, 30),
                       (11, 12, 13), Prior((0.0, 1.1, 0.4), (0.05, 0.05, 0.05)))


def test_measured_runs_report_the_true_regret_of_what_was_observed():
    from ergohandover.study.measured_answers import measured_summary, run_measured_job
    from ergohandover.study.personalise import values_of

    job = measured_job(0.0)
    values = values_of(job)
    exact = pd.DataFrame(run_measured_job(job))
    assert len(exact) == 3 * 3 and (exact["optimum_score"] == values.min()).all()
    # Without error the measured score is the true one, and more handovers never do worse.
    assert (exact["measured_score"] == exact["true_score"]).all()
    for _, one in exact.groupby("run"):
        assert one["regret"].is_monotonic_decreasing and (one["regret"] >= 0).all()
    noisy = pd.DataFrame(run_measured_job(measured_job(10.0)))
    assert noisy.equals(pd.DataFrame(run_measured_job(measured_job(10.0))))  # seeded
    assert (noisy["regret"] >= 0).all()
    assert (noisy["measured_score"] != noisy["true_score"]).any()  # the error shows
    summary = measured_summary(pd.concat([exact, noisy]), seed=0)
    assert len(summary) == 2 * 3
    for _, row in summary.iterrows():
        assert row.ci_low <= row.p_regret_0 <= row.ci_high
        assert row.regret_ci_low <= row.mean_regret <= row.regret_ci_high
