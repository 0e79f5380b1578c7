"""The paper's postural score on hand-worked cases, quirks included."""

from __future__ import annotations

import pytest
from conftest import neutral_columns

from ergohandover.ergonomics import Posture, score_postures


def paper(**overrides) -> dict[str, int]:
    s = score_postures(Posture(neutral_columns(**overrides)))
    return {k: int(v[0]) for k, v in s.items() if k.startswith("paper_")}


def test_upright_with_elbows_at_80_scores_5():
    # neck 1 + trunk 1 + legs 1 + hands 0 + arm (upper 1 + lower 1)
    assert paper()["paper_postural"] == 5


def test_the_practical_minimum_is_4_with_elbows_under_60():
    # An elbow under 60° scores 0 in the paper's rule (REBA: 2).
    s = paper(left_elbow_flexion=40.0, right_elbow_flexion=40.0)
    assert s["paper_postural"] == 4 and s["paper_left_arm"] == 1


def test_a_hand_worked_stooped_posture():
    s = paper(trunk_flexion=10.0, trunk_twist=5.0, neck_flexion=25.0, left_knee_flexion=45.0,
              right_knee_flexion=45.0, hands_above_neck=1.0,
              left_upper_arm_flexion=30.0, left_elbow_flexion=50.0,
              right_upper_arm_flexion=10.0, right_elbow_flexion=110.0)
    assert s == {"paper_neck": 2, "paper_trunk": 4, "paper_legs": 2,
                 "paper_hands_above_neck": 1, "paper_left_arm": 2, "paper_right_arm": 3,
                 "paper_postural": 2 + 4 + 2 + 1 + 3}


@pytest.mark.parametrize(("knee", "legs"), [
    (0.0, 1), (2.0, 1), (2.01, 2), (59.99, 2), (60.0, 1), (60.01, 3), (120.0, 3),
])
def test_legs_quirk_exactly_60_adds_nothing(knee, legs):
    assert paper(left_knee_flexion=knee)["paper_legs"] == legs


@pytest.mark.parametrize(("flexion", "twist", "trunk"), [
    (0.0, 0.0, 1), (3.0, 0.0, 1), (-3.0, 0.0, 1), (3.01, 0.0, 3), (-3.01, 0.0, 2),
    (70.0, 0.0, 3), (0.0, 2.0, 1), (0.0, -2.01, 2), (30.0, 5.0, 4),
])
def test_trunk_bands_and_twist(flexion, twist, trunk):
    assert paper(trunk_flexion=flexion, trunk_twist=twist)["paper_trunk"] == trunk


def test_trunk_side_bend_is_not_counted():
    assert paper(trunk_side_bend=40.0)["paper_trunk"] == 1


@pytest.mark.parametrize(("column", "value", "neck"), [
    ("neck_flexion", -15.0, 1),   # REBA would score extension 2
    ("neck_flexion", 20.0, 1), ("neck_flexion", 20.01, 2), ("neck_flexion", -20.01, 2),
    ("neck_side_bend", 21.0, 2), ("neck_twist", -21.0, 2), ("neck_twist", 19.0, 1),
])
def test_neck_uses_the_largest_magnitude(column, value, neck):
    assert paper(**{column: value})["paper_neck"] == neck


@pytest.mark.parametrize(("flexion", "elbow", "arm"), [
    (-25.0, 40.0, 0), (-20.0, 60.0, 2), (20.0, 100.0, 2), (20.01, 100.01, 4),
    (100.0, 59.9, 2),  # flexion beyond 45° and 90° is not graded
])
def test_arm_bands(flexion, elbow, arm):
    s = paper(right_upper_arm_flexion=flexion, right_elbow_flexion=elbow)
    assert s["paper_right_arm"] == arm


def test_the_larger_arm_total_is_added():
    s = paper(left_upper_arm_flexion=30.0, left_elbow_flexion=120.0,
              right_upper_arm_flexion=-30.0, right_elbow_flexion=30.0)
    assert (s["paper_left_arm"], s["paper_right_arm"]) == (4, 0)
    assert s["paper_postural"] == 3 + 4


def test_wrist_load_coupling_and_activity_do_not_count():
    base = paper()["paper_postural"]
    assert paper(left_wrist_flexion=60.0, load_kg=20.0, coupling=3.0, activity=3.0,
                 shock=1.0)["paper_postural"] == base
