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
from ergohandover.study.personalise.measured import MeasuredScores
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


@pytest.mark.slow
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
    from ergohandover.study.personalise.measured_answers import recommendation

    scores = [math.inf, 7.0, 5.0, 6.0, 5.0, 4.0]
    assert recommendation(scores, 2) == 1
    assert recommendation(scores, 5) == 2  # the first of equals
    assert recommendation(scores, 6) == 5
    assert recommendation([math.inf, math.inf], 2) is None


def measured_job(answers, searcher: str = "cmaes+prior", twin: str = "in-model",
                 evaluator: Evaluator = EVALUATOR):
    from ergohandover.search.prior import Prior
    from ergohandover.study.personalise.measured_answers import MeasuredJob

    return MeasuredJob("w1", twin, evaluator, GRID, "paper_postural", searcher, answers,
                       (3, 10, 30), (11, 12, 13), Prior((0.0, 1.1, 0.4), (0.05, 0.05, 0.05)))


@pytest.mark.slow
def test_measured_runs_report_the_true_regret_of_what_was_observed():
    from ergohandover.study.personalise.measured_answers import (
        Answers,
        measured_summary,
        run_measured_job,
        truth_of,
    )

    job = measured_job(Answers("posture", 0.0))
    values = truth_of(job)
    exact = pd.DataFrame(run_measured_job(job))
    assert len(exact) == 3 * 3 * 2 and (exact["optimum_score"] == values.min()).all()
    assert set(exact["answers"]) == {"exact"}
    assert set(exact["rule"]) == {"lowest", "confirm"}  # no candidates: no model of the worker
    lowest = exact[exact["rule"] == "lowest"]
    # Without error the answer is the true score, and more handovers never do worse.
    assert (lowest["answer"] == lowest["true_score"]).all()
    for _, one in lowest.groupby("run"):
        assert one["regret"].is_monotonic_decreasing and (one["regret"] >= 0).all()
    # Confirming spends the budget's last fifth measuring again: fewer locations searched.
    confirm = exact[exact["rule"] == "confirm"]
    assert (confirm["handovers"] <= confirm["budget"]).all()
    assert (confirm["regret"].to_numpy() >= lowest["regret"].to_numpy()).all()
    noisy = pd.DataFrame(run_measured_job(measured_job(Answers("posture", 10.0))))
    assert noisy.equals(pd.DataFrame(run_measured_job(measured_job(Answers("posture", 10.0)))))
    assert (noisy["regret"] >= 0).all()
    assert (noisy["answer"] != noisy["true_score"]).any()  # the error shows
    rated = pd.DataFrame(run_measured_job(measured_job(Answers("rater", 0.51))))
    assert (rated["answer"] % 0.5 == 0).all()  # whole scores, or the mean of two
    baseline = pd.Series({"w1|in-model": 1.0})  # one handover at the prior's: 1 point off
    summary = measured_summary(pd.concat([exact, noisy, rated]), baseline, seed=0)
    assert len(summary) == 3 + 3 * 2 * 3  # no search per answer model, then every rule
    nothing = summary[summary["searcher"] == "no search"]
    assert (nothing["mean_regret"] == 1.0).all() and (nothing["gain"] == 0).all()
    for _, row in summary.iterrows():
        assert row.ci_low <= row.p_regret_0 <= row.ci_high
        assert row.regret_ci_low <= row.mean_regret <= row.regret_ci_high
        assert row.gain == pytest.approx(1.0 - row.mean_regret)  # paired with the baseline
        assert row.harm_ci_low <= row.harm <= row.harm_ci_high


def test_a_rows_intervals_do_not_move_when_another_rows_runs_change():
    from ergohandover.study.personalise.measured_answers import measured_summary

    rng = np.random.default_rng(3)
    units = [f"w{i}" for i in range(12)]

    def runs(searcher: str, regret: np.ndarray) -> pd.DataFrame:
        return pd.DataFrame({"worker": np.repeat(units, 3), "twin": "in-model",
                             "searcher": searcher, "answers": "posture SD 5 deg",
                             "rule": "model", "budget": 10, "handovers": 10,
                             "regret": regret, "p_optimal": 0.5})

    kept = runs("kept", rng.integers(0, 3, 36).astype(float))
    before = runs("changed", np.zeros(36))  # every worker alike: no bootstrap drawn
    after = runs("changed", rng.integers(0, 3, 36).astype(float))
    baseline = pd.Series({f"{u}|in-model": 1.0 for u in units})

    def kept_row(other: pd.DataFrame) -> pd.Series:
        summary = measured_summary(pd.concat([other, kept]), baseline, seed=0)
        return summary[summary["searcher"] == "kept"].iloc[0]

    first, second = kept_row(before), kept_row(after)
    assert first["regret_ci_low"] < first["mean_regret"] < first["regret_ci_high"]
    for column in ("ci_low", "ci_high", "regret_ci_low", "regret_ci_high", "gain_ci_low",
                   "gain_ci_high", "harm_ci_low", "harm_ci_high"):
        assert first[column] == second[column], column


@pytest.mark.slow
def test_a_worker_whose_twin_differs_is_scored_by_that_twin():
    import dataclasses

    from ergohandover.study.personalise.measured_answers import Answers, run_measured_job, truth_of

    other = dataclasses.replace(EVALUATOR, task=dataclasses.replace(EVALUATOR.task, gaze="off"))
    job = measured_job(Answers("posture", 0.0), twin="gaze off", evaluator=other)
    values = truth_of(job)
    assert not np.array_equal(values, truth_of(measured_job(Answers("posture", 0.0))))
    rows = pd.DataFrame(run_measured_job(job))
    assert (rows["twin"] == "gaze off").all() and (rows["optimum_score"] == values.min()).all()
    lowest = rows[rows["rule"] == "lowest"]
    assert (lowest["true_score"] == values[lowest["cell"].to_numpy()]).all()


def test_the_confirm_rule_measures_the_best_again_and_recommends_the_lowest_mean():
    from ergohandover.study.personalise.measured_answers import confirmations, confirmed

    cells = [10, 11, 12, 13, 14, 15, 16, 17, 18, 19]
    scores = [5.0, 3.0, math.inf, 4.0, 3.0, 6.0, 7.0, 2.0, 9.0, 9.0]
    assert confirmations(10) == 2 and confirmations(4) == 1
    # At budget 10: 8 searched, the two lowest (2 at cell 17, then the first 3, at cell 11)
    # measured again; the second answers change which is lower.
    again = {17: 6.0, 11: 2.0}
    asked = []

    def measure(cell):
        asked.append(cell)
        return again[cell]

    index, mean, spent = confirmed(cells, scores, 10, measure)
    assert asked == [17, 11] and index == 1 and mean == 2.5 and spent == 10
    index, _, spent = confirmed(cells, [math.inf] * 10, 10, measure)
    assert index is None and spent == 8
    with pytest.raises(ConfigError, match="budget = 1 is outside"):
        confirmed(cells, scores, 1, measure)


def test_a_rater_gives_whole_scores_whose_reliability_is_the_icc():
    from ergohandover.study.personalise.measured import RatedScores, rater_sd

    rng = np.random.default_rng(0)
    values = rng.integers(2, 9, 400).astype(float)
    values[:5] = np.inf
    grid = Grid(Boundary((0, 0.19), (0, 0.09), (0, 0.01)), 0.01)  # 20 x 10 x 2 = 400 cells
    assert grid.size == values.size
    for icc in (0.89, 0.51):
        rater = RatedScores(grid, values, rater_sd(values, icc), np.random.default_rng(1))
        first = np.array([rater.score(c) for c in range(400)])
        second = np.array([rater.score(c) for c in range(400)])
        assert np.isinf(first[:5]).all() and (first[5:] % 1 == 0).all() and first.min() >= 1
        a, b = first[5:], second[5:]
        # The one-way ICC of two ratings of each posture: near the published one (rounding
        # adds a little error of its own).
        within = ((a - b) ** 2).mean() / 2
        between = np.concatenate([a, b]).var()
        assert abs((between - within) / between - icc) < 0.08
    with pytest.raises(ConfigError, match=r"icc = 0\.0 is outside"):
        rater_sd(values, 0.0)
    with pytest.raises(ConfigError, match=r"rater ICC = 1\.5 is outside"):
        from ergohandover.study.personalise.measured_answers import Answers
        Answers("rater", 1.5)


def test_with_a_prior_bayesian_optimisation_starts_from_the_priors_design():
    from ergohandover.search.optuna_searchers import PRIOR_DESIGN
    from ergohandover.search.prior import Prior

    grid = Grid(Boundary((-0.3, 0.3), (0.8, 1.4), (0.2, 0.6)), 0.02)
    prior = Prior((0.0, 1.1, 0.4), (0.03, 0.03, 0.03))
    for name in ("bo+prior", "tpe+prior"):
        searcher = make(name, grid, 5, prior)
        cells = []
        for _ in range(PRIOR_DESIGN):
            cell = searcher.ask()
            cells.append(cell)
            searcher.tell(cell, 5.0)
        points = grid.coordinates(cells)
        assert np.allclose(points[0], prior.location, atol=grid.step / 2 + 1e-9)
        assert len(set(cells)) == PRIOR_DESIGN
        # Drawn from the prior: within a few SDs of it, not anywhere on the grid.
        assert (np.abs(points - prior.location) <= 4 * 0.03 + grid.step).all()
