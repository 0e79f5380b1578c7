"""The analyses behind the headlines: posture error as an instrument was measured to make it,
the robust location that keeps the worker's optimum, the one-size location scored out of bag,
the pre-specified who-pays tests and the learning study's ceiling."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ergohandover.errors import ConfigError
from ergohandover.landscape.stats import minimum
from ergohandover.robustness.measured_error import (
    MEASURED_ERROR,
    MEASURED_VARIANTS,
    JointError,
    MeasuredError,
)
from ergohandover.robustness.posture_error import ANGLE_COLUMNS, ErrorModel, monte_carlo
from ergohandover.robustness.search import robust_optimum
from ergohandover.study.population.who_pays import (
    PLANNED,
    restricted_cubic_spline,
    sex_and_stature_tests,
    with_holm,
)
from ergohandover.study.robustness.analysis import without_optimism

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))
sys.path.insert(0, str(ROOT / "tests"))

import learning_tables  # noqa: E402
from test_robustness import upright  # noqa: E402


def drawn(model, n: int = 200_000) -> pd.DataFrame:
    errors = model.errors(n, np.random.default_rng(5))
    return pd.DataFrame({c: errors[c].astype(float) for c in ANGLE_COLUMNS})


def test_measured_error_draws_have_each_angles_bias_sd_and_the_stated_correlations():
    frame = drawn(MEASURED_ERROR)
    table = MEASURED_ERROR.table().set_index("angle")
    for column in ANGLE_COLUMNS:
        bare = column.split("_", 1)[1] if column.startswith(("left_", "right_")) else column
        assert frame[column].mean() == pytest.approx(table.loc[bare, "bias_deg"], abs=0.06)
        assert frame[column].std() == pytest.approx(table.loc[bare, "sd_deg"], rel=0.01)
    corr = frame.corr()
    rho_in, rho_sides = MEASURED_ERROR.within_segment, MEASURED_ERROR.between_sides
    assert corr.loc["trunk_flexion", "trunk_twist"] == pytest.approx(rho_in, abs=0.01)
    assert corr.loc["left_upper_arm_flexion", "left_upper_arm_abduction"] == pytest.approx(
        rho_in, abs=0.01)
    assert corr.loc["left_knee_flexion", "right_knee_flexion"] == pytest.approx(rho_sides,
                                                                                abs=0.01)
    assert abs(corr.loc["trunk_flexion", "left_elbow_flexion"]) < 0.01  # other segments
    assert abs(corr.loc["left_elbow_flexion", "left_upper_arm_flexion"]) < 0.01
    # Across a segment and the sides: the product, so no combination of errors is fixed.
    assert corr.loc["left_upper_arm_flexion", "right_upper_arm_abduction"] == pytest.approx(
        rho_in * rho_sides, abs=0.01)
    across = ((frame["left_upper_arm_flexion"] - frame["left_upper_arm_abduction"])
              - (frame["right_upper_arm_flexion"] - frame["right_upper_arm_abduction"]))
    assert across.std() > 1.0
    assert np.linalg.eigvalsh(MEASURED_ERROR.correlation()).min() > 0.1


def test_the_variants_drop_the_correlations_and_scale_only_the_sds():
    plain = drawn(MEASURED_VARIANTS["uncorrelated"]).corr()
    assert abs(plain.loc["left_knee_flexion", "right_knee_flexion"]) < 0.01
    wide = drawn(MEASURED_VARIANTS["SDs x1.5"])
    base = drawn(MEASURED_ERROR)
    arm = "left_upper_arm_flexion"
    assert wide[arm].std() == pytest.approx(1.5 * base[arm].std(), rel=0.01)
    assert wide[arm].mean() == pytest.approx(base[arm].mean(), abs=0.06)


def test_a_measured_error_model_must_cover_every_angle_and_have_valid_correlations():
    joints = dict(MEASURED_ERROR.joints)
    del joints["wrist_twist"]
    with pytest.raises(ConfigError, match="wrist_twist"):
        dataclasses.replace(MEASURED_ERROR, joints=joints)
    with pytest.raises(ConfigError, match=r"between_sides = 1\.2"):
        dataclasses.replace(MEASURED_ERROR, between_sides=1.2)
    with pytest.raises(ConfigError, match="valid covariance"):
        # Pairs within a segment and between sides can each be allowed and not all together.
        dataclasses.replace(MEASURED_ERROR, within_segment=-0.9, between_sides=0.95)


def test_a_bias_moves_the_measured_score_the_way_it_points():
    """A trunk error biased towards flexion measures a neutral trunk as flexed: REBA's trunk
    item rises; unbiased error of the same SD leaves it mostly neutral."""
    still = {k: JointError(0.0, 0.0, "test") for k in MEASURED_ERROR.joints}
    biased = MeasuredError("biased", "test", still | {"trunk_flexion": JointError(
        25.0, 1.0, "test")}, 0.0, 0.0)
    level = MeasuredError("level", "test", still | {"trunk_flexion": JointError(
        0.0, 1.0, "test")}, 0.0, 0.0)
    posture = upright()
    moved = monte_carlo(posture, biased, 500, np.random.default_rng(0))
    kept = monte_carlo(posture, level, 500, np.random.default_rng(0))
    assert moved.mean["reba"][0] > kept.mean["reba"][0]
    assert kept.p_nominal_or_better["reba"][0] > 0.5 > moved.p_nominal_or_better["reba"][0]


def test_the_robust_location_among_optima_keeps_the_error_free_optimum(small_landscape):
    evaluator, landscape = small_landscape
    values = landscape.arrays["paper_postural"]
    best = minimum(landscape, "paper_postural")
    for tolerance in (0, 1):
        found = robust_optimum(landscape, evaluator, ErrorModel(5.0), "paper_postural", 500, 0,
                               stride=2, screen_draws=64, keep=4, radius=1,
                               tolerance=tolerance)
        assert values[found.cell] <= best + tolerance
        assert landscape.feasible[found.cell]
        assert (found.screened["nominal"] <= best + tolerance).all()


def test_out_of_bag_scores_a_one_size_choice_only_on_workers_it_was_not_chosen_on():
    """Each worker prefers a cell of their own, tied with others' for the mean: chosen on a
    resample, the cell is one of its workers', so on the workers left out it costs them all
    while on the resample it looks cheaper."""
    workers = 30
    scores = np.full((workers, workers), 2.0)
    np.fill_diagonal(scores, 1.0)
    points = np.column_stack([np.linspace(-0.1, 0.1, workers), np.ones(workers),
                              np.full(workers, 0.4)])
    rows = {r["choice"]: r for r in without_optimism(
        scores, scores.min(axis=1), points, 0, np.random.default_rng(1), 200, 20)}
    mean = rows["mean"]
    assert mean["out_of_bag_mean_penalty"] == pytest.approx(1.0)  # never their own cell
    assert mean["rechosen_mean_penalty"] < mean["out_of_bag_mean_penalty"]
    assert mean["out_of_bag_ci_low"] <= 1.0 <= mean["out_of_bag_ci_high"]


def test_the_spline_is_linear_beyond_its_outer_knots_and_bends_between():
    knots = np.array([1.5, 1.65, 1.75, 1.9])
    x = np.linspace(1.2, 2.2, 201)
    basis = restricted_cubic_spline(x, knots)
    assert basis.shape == (201, 3)
    np.testing.assert_allclose(basis[:, 0], x)
    second = np.diff(basis[:, 1:], n=2, axis=0)
    outside = (x[1:-1] < knots[0]) | (x[1:-1] > knots[-1] + 0.006)
    np.testing.assert_allclose(second[outside], 0, atol=1e-12)
    assert np.abs(second[~outside]).max() > 1e-6


def test_the_planned_tests_see_a_v_shaped_stature_effect_that_a_line_blames_on_sex():
    """Penalty rises on both sides of 1.75 m and does not depend on sex; the women stand on
    one side of the bowl, the men spread across it. A straight line in stature leaves the
    curvature the men's spread adds to their penalty to sex; the spline does not."""
    rng = np.random.default_rng(0)
    n = 400
    male = (np.arange(n) % 2).astype(float)
    stature = np.where(male == 1, rng.normal(1.75, 0.10, n), rng.normal(1.60, 0.03, n))
    penalty = 4 * np.abs(stature - 1.75) + rng.normal(0, 0.05, n)
    others = {"elbow": rng.normal(0.62, 0.01, n), "arm": rng.normal(0.44, 0.01, n)}
    table = pd.DataFrame(sex_and_stature_tests(penalty, stature, male, others)).set_index(
        ["question", "model"])
    line = table.loc[("sex beyond body size", "straight line, OLS errors")]
    planned = table.loc[("sex beyond body size", PLANNED)]
    assert line["p"] < 0.001  # the line's spurious sex effect
    assert planned["p"] > 0.05 and planned["ci_low"] < 0 < planned["ci_high"]
    assert table.loc[("stature", PLANNED), "p"] < 1e-6


def test_holm_adjusts_only_the_plans_family_and_few_workers_give_no_test():
    rng = np.random.default_rng(2)
    n = 60
    stature, male = rng.normal(1.7, 0.09, n), (np.arange(n) % 2).astype(float)
    rows = []
    for k in range(3):
        rows += [{"objective": "paper_postural", "choice": f"c{k}", **r}
                 for r in sex_and_stature_tests(rng.normal(1, 0.5, n), stature, male,
                                                {"e": rng.normal(0, 1, n)})]
    table = with_holm(pd.DataFrame(rows))
    planned = table["model"] == PLANNED
    assert table.loc[~planned, "p_holm"].isna().all()
    assert (table.loc[planned, "p_holm"] >= table.loc[planned, "p"]).all()
    assert (table["family"] == 6).all()  # 2 questions x 3 locations
    assert sex_and_stature_tests(rng.normal(1, 0.5, 5), stature[:5], male[:5],
                                 {"e": rng.normal(0, 1, 5)}) == []  # too few workers
    assert sex_and_stature_tests(np.ones(n), stature, male, {}) == []  # nobody pays differently
    assert with_holm(pd.DataFrame()).empty


def test_learning_ties_at_the_ceiling_are_not_called_equivalent():
    rows = pd.DataFrame({"successes_agent": [100, 99, 80, 100], "successes_versus": [100, 100,
                                                                                      81, 100],
                         "n": 100, "verdict": ["equivalent within ±10 pp"] * 3 + ["worse"]})
    assert list(learning_tables.verdicts(rows)) == [
        learning_tables.CEILING, learning_tables.CEILING, "equivalent within ±10 pp", "worse"]
