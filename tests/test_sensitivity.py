"""The sensitivity study's variants change exactly one modelling choice each, and its rows say
what the landscape says."""

from __future__ import annotations

import numpy as np
import pytest

from ergohandover.landscape import landscape_of
from ergohandover.landscape.cache import landscape_key
from ergohandover.landscape.grid import Grid
from ergohandover.landscape.stats import minimisers, optimum
from ergohandover.study.sensitivity.variants import OBJECTIVES, Variant, sensitivity_row, variants
from ergohandover.twin.evaluate import EvaluationError, Evaluator, evaluate_arrays, posture_solver
from ergohandover.twin.solver import SolverSettings, SolverSettingsError
from ergohandover.twin.task import Boundary, TaskSpec

SMALL = Boundary((-0.10, 0.10), (0.95, 1.25), (0.32, 0.47))


def test_there_are_twenty_variants_each_with_its_own_landscape():
    base = Evaluator()
    chosen = variants(base)
    assert chosen[0].group == "default" and len(chosen) - 1 >= 20
    assert len({v.name for v in chosen}) == len(chosen)
    grid = Grid(SMALL, 0.05)
    keys = {landscape_key(v.evaluator(base), grid) for v in chosen}
    assert len(keys) == len(chosen)  # no variant is the default in disguise
    groups = {v.group for v in chosen}
    assert {"solver weight", "joint preference", "knee strategy", "gaze", "joint limits",
            "trunk angle", "box"} <= groups


def test_a_variant_changes_only_what_it_names():
    base = Evaluator()
    hand = next(v for v in variants(base) if v.name == "hand x2").evaluator(base)
    assert hand.settings.hand == 2 * base.settings.hand
    assert hand.task == base.task and hand.scoring == base.scoring and hand.body == base.body
    narrow = next(v for v in variants(base) if v.name == "handle span x0.5").evaluator(base)
    assert narrow.task.handle_span == pytest.approx(0.20)
    assert narrow.task.handle_span >= narrow.task.box_width


@pytest.mark.slow
def test_joint_preference_and_range_of_motion_settings_reach_the_solver():
    base = posture_solver(Evaluator())
    legs = posture_solver(Evaluator(settings=SolverSettings(
        joint_preference_scales=(("knee_flexion", 2.0),))))
    knee = base.model.index("knee_flexion")
    assert legs.preference[knee] == 2 * base.preference[knee]
    others = np.arange(base.model.nq) != knee
    np.testing.assert_array_equal(legs.preference[others], base.preference[others])
    assert posture_solver(Evaluator(settings=SolverSettings(preference_scale=0.5))) \
        .preference == pytest.approx(0.5 * base.preference)
    small = posture_solver(Evaluator(settings=SolverSettings(range_of_motion=0.5)))
    np.testing.assert_allclose(small.model.upper, 0.5 * base.model.upper)
    np.testing.assert_allclose(small.model.lower, 0.5 * base.model.lower)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"joint_preference_scales": (("tail_wag", 2.0),)}, "joint_preference_scales: 'tail_wag'"),
    ({"preference_scale": 0.0}, "preference_scale = 0.0 is outside"),
    ({"range_of_motion": 1.5}, "range_of_motion = 1.5 is outside"),
])
def test_bad_solver_settings_are_one_line_errors(kwargs, message):
    with pytest.raises(SolverSettingsError, match=message):
        posture_solver(Evaluator(settings=SolverSettings(**kwargs)))


@pytest.mark.slow
def test_the_trunk_relative_to_the_pelvis_is_smaller_when_the_hips_flex():
    low = np.array([[0.0, 0.55, 0.40]])  # a low box: the pelvis tilts forward with the hips
    columns = ("trunk_flexion", "neck_flexion")
    vertical = evaluate_arrays(low, Evaluator(), columns=columns)
    pelvis = evaluate_arrays(low, Evaluator(trunk_reference="pelvis"), columns=columns)
    assert vertical["trunk_flexion"][0] > 20
    assert 0 <= pelvis["trunk_flexion"][0] < vertical["trunk_flexion"][0] - 5
    assert pelvis["neck_flexion"][0] == vertical["neck_flexion"][0]
    with pytest.raises(EvaluationError, match="trunk_reference = 'hips' is not allowed"):
        Evaluator(trunk_reference="hips")


@pytest.mark.slow
def test_a_row_reports_the_landscapes_minima_optimum_and_the_conclusion():
    grid = Grid(SMALL, 0.05)
    base = Evaluator()
    landscape = landscape_of(base, grid, progress=False)
    row = sensitivity_row(Variant("default", "default"), landscape, base, None)
    for score in OBJECTIVES:
        cells = minimisers(landscape, score)
        assert row[f"{score}_min"] == landscape.arrays[score][cells[0]]
        assert row[f"{score}_fraction_at_min"] == len(cells) / landscape.feasible.sum()
    best = optimum(landscape)[1]
    assert (row["optimum_x"], row["optimum_y"], row["optimum_z"]) == tuple(best)
    assert np.isnan(row["shift_cm"])  # no reference given
    assert row["optimum_paper_postural"] == row["paper_postural_min"]
    assert row["conclusion_holds"] == (row["best_shortest_distance_paper_postural"]
                                       > row["optimum_paper_postural"])
    off = Evaluator(task=TaskSpec(gaze="off"))
    other = landscape_of(off, grid, progress=False)
    shifted = sensitivity_row(Variant("gaze", "gaze off"), other, off, best)
    moved = np.array([shifted["optimum_x"], shifted["optimum_y"], shifted["optimum_z"]]) - best
    assert shifted["shift_cm"] == pytest.approx(np.linalg.norm(moved) * 100)
