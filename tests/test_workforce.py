"""The sampled workforce: seeded, the exact sex mix, the survey's statistics, the model's range;
and the population study's arithmetic (one-size choices, penalties, fits) on known matrices."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ergohandover.errors import ConfigError
from ergohandover.search.statistics import wilson
from ergohandover.study.population.one_size import (
    line_fit,
    one_size_cells,
    penalty_summary,
    stature_band,
    working_heights,
)
from ergohandover.study.workforce import Workforce, bodies, landmark_columns, sample_workforce
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.body_model import body_model


def test_the_same_seed_draws_the_same_workers_and_another_seed_others():
    a = sample_workforce(Workforce(30, seed=5))
    b = sample_workforce(Workforce(30, seed=5))
    c = sample_workforce(Workforce(30, seed=6))
    assert a.equals(b)
    assert not np.array_equal(a["stature_m"], c["stature_m"])
    assert list(a["worker"][:2]) == ["w001", "w002"] and a["worker"].is_unique


@pytest.mark.parametrize(("size", "share", "women"), [(30, 0.5, 15), (7, 0.3, 2), (5, 0.0, 0),
                                                      (4, 1.0, 4)])
def test_the_sex_mix_is_exact(size, share, women):
    table = sample_workforce(Workforce(size, seed=1, female_share=share))
    assert len(table) == size and (table["sex"] == "female").sum() == women


@pytest.mark.slow
def test_a_large_draw_has_the_body_models_means_sds_and_correlations():
    table = sample_workforce(Workforce(4_000, seed=3))
    for sex, rows in table.groupby("sex"):
        model = body_model()[sex]
        n = len(rows)
        for name in ("stature_m", "mass_kg", "shoulder_height_m", "wrist_height_m"):
            k = model.names.index(name)
            assert abs(rows[name].mean() - model.mean[k]) < 4 * model.sd[k] / math.sqrt(n)
            assert abs(rows[name].std() - model.sd[k]) < 0.08 * model.sd[k]
        i, j = model.names.index("stature_m"), model.names.index("shoulder_height_m")
        assert abs(np.corrcoef(rows["stature_m"], rows["shoulder_height_m"])[0, 1]
                   - model.correlation[i, j]) < 0.02


def test_workers_proportions_vary_as_the_surveys_do():
    table = sample_workforce(Workforce(400, seed=4))
    marks = landmark_columns(bodies(table))
    # The survey's SD of elbow height / stature is about 0.010 within each sex; a twin scaled
    # from stature alone would have none.
    for sex in ("female", "male"):
        ratio = marks["elbow_ratio"][table["sex"] == sex]
        assert 0.007 < ratio.std() < 0.013
        assert 0.59 < ratio.mean() < 0.63


def test_every_worker_is_a_valid_body_at_the_surveys_resolution():
    table = sample_workforce(Workforce(500, seed=9))
    specs = bodies(table)  # BodySpec validates the range and the anatomical order
    assert all(isinstance(b, BodySpec) for b in specs)
    assert specs[0].measurements and dict(specs[0].measurements)["shoulder_height_m"] == \
        table["shoulder_height_m"].iloc[0]
    np.testing.assert_allclose(table["stature_m"], table["stature_m"].round(3), atol=1e-12)
    np.testing.assert_allclose(table["mass_kg"], table["mass_kg"].round(1), atol=1e-12)


@pytest.mark.parametrize(("field", "kwargs", "allowed"), [
    ("size", {"size": 0}, "at least 1"), ("size", {"size": 2.5}, "at least 1"),
    ("seed", {"seed": -1}, "at least 0"), ("female_share", {"female_share": 1.5}, "0-1")])
def test_bad_workforce_values_are_one_line_errors(field, kwargs, allowed):
    with pytest.raises(ConfigError, match=f"{field} = .* outside the valid range.*{allowed}"):
        Workforce(**kwargs)


def test_one_size_choices_on_a_known_matrix():
    nan = np.nan
    # 4 workers x 5 cells; cell 4 is infeasible for worker 2, so it is no one-size candidate
    # even though it has the lowest scores elsewhere.
    scores = np.array([[5, 4, 6, 5, 1],
                       [5, 6, 4, 5, 1],
                       [5, 6, 6, 5, nan],
                       [5, 4, 6, 7, 1]], dtype=float)
    points = np.array([[0.1, 1, 0.4], [0.0, 1, 0.4], [0.0, 1.1, 0.4], [0.0, 1.2, 0.4],
                       [0.0, 0.9, 0.4]])
    cells = one_size_cells(scores, points, reference_cell=2)
    # Means: 5, 5, 5.5, 5.5; the lowest, 5, at cells 0 and 1: cell 1 is the more symmetric.
    assert cells["mean"] == 1
    # 95th percentiles (an observed score): 5, 6, 6, 7: cell 0, though its mean ties cell 1.
    assert cells["p95"] == 0
    assert cells["reference"] == 2


def test_the_p95_choice_breaks_ties_by_the_mean():
    scores = np.array([[3, 1], [3, 2], [3, 3]], dtype=float)  # both p95 = 3; means 3 and 2
    assert one_size_cells(scores, np.array([[0.0, 1, 0.4], [0.1, 1, 0.4]]), 0)["p95"] == 1


def test_no_cell_feasible_for_all_is_a_one_line_error():
    scores = np.array([[1.0, np.nan], [np.nan, 1.0]])
    with pytest.raises(ConfigError, match="no location of the grid is feasible for every"):
        one_size_cells(scores, np.zeros((2, 3)), 0)


def test_penalty_summary_counts_and_intervals():
    summary = penalty_summary(np.array([0.0, 1.0, 2.0, np.nan]),
                              np.random.default_rng(0), 500)
    assert summary["n"] == 4 and summary["infeasible_for"] == 1
    assert summary["mean_penalty"] == pytest.approx(1.0)
    assert summary["mean_ci_low"] <= 1.0 <= summary["mean_ci_high"]
    assert summary["share_penalised"] == pytest.approx(2 / 3)
    assert (summary["share_penalised_ci_low"], summary["share_penalised_ci_high"]) == \
        pytest.approx(wilson(2, 3))
    assert summary["share_penalised_2plus"] == pytest.approx(1 / 3)
    assert summary["max_penalty"] == 2.0


def test_a_line_fit_recovers_an_exact_line_and_brackets_a_noisy_one():
    x = np.linspace(1.5, 1.9, 25)
    exact = line_fit(x, 0.2 + 0.6 * x, np.random.default_rng(1), 300)
    assert exact["slope"] == pytest.approx(0.6) and exact["intercept"] == pytest.approx(0.2)
    assert exact["r2"] == pytest.approx(1.0) and exact["residual_sd"] < 1e-12
    assert exact["slope_ci_low"] == pytest.approx(0.6) == exact["slope_ci_high"]
    noisy = line_fit(x, 0.2 + 0.6 * x + np.random.default_rng(2).normal(0, 0.02, x.size),
                     np.random.default_rng(3), 2000)
    assert noisy["slope_ci_low"] < 0.6 < noisy["slope_ci_high"]
    assert noisy["residual_sd"] == pytest.approx(0.02, rel=0.4)


def test_stature_bands_include_their_lower_edge():
    bands = stature_band(np.array([1.55, 1.60, 1.699, 1.70, 1.80, 1.95]))
    assert list(bands) == ["< 1.60 m", "1.60-1.70 m", "1.60-1.70 m", "1.70-1.80 m",
                           ">= 1.80 m", ">= 1.80 m"]


def test_optima_are_counted_in_each_published_working_height_range():
    table = working_heights(np.array([5.0, 7.5, 10.0, 12.0, 20.0])).set_index("low_cm")
    # The validation's sources: 5-10 cm (Pheasant & Haslegrave), 10-15 cm (Grandjean),
    # 17-22 cm (Magnusson & Ortengren) below elbow height; both ends included.
    assert table.loc[5.0, "within"] == 3 and table.loc[10.0, "within"] == 2
    assert table.loc[17.0, "within"] == 1
    assert (table["n"] == 5).all()
    assert (table.loc[5.0, "ci_low"], table.loc[5.0, "ci_high"]) == pytest.approx(wilson(3, 5))
