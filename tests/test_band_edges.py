"""Every band edge of every item, on both sides, in both band-edge modes, for both arms.

Each row: the item score, the column(s) moved, the edge (deg or kg) and the item's score just
below and just above it, as the worksheet states (default settings: 5° neutral tolerance,
10° twist/side bend/deviation/shoulder raise, 20° abduction/rotation, 30° wrist twist).
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest
from conftest import neutral_columns

from ergohandover.ergonomics import Posture, ScoringSettings, score_postures

EPS = 1e-6


def arm_rows(prefix: str) -> list[tuple]:
    rows = []
    for side in ("left", "right"):
        def col(name, side=side):
            return f"{side}_{name}"
        if prefix == "reba":
            rows += [
                (f"reba_{side}_upper_arm", col("upper_arm_flexion"), -20, 2, 1),
                (f"reba_{side}_upper_arm", col("upper_arm_flexion"), 20, 1, 2),
                (f"reba_{side}_upper_arm", col("upper_arm_flexion"), 45, 2, 3),
                (f"reba_{side}_upper_arm", col("upper_arm_flexion"), 90, 3, 4),
                (f"reba_{side}_upper_arm", col("upper_arm_abduction"), 20, 1, 2),
                (f"reba_{side}_upper_arm", col("upper_arm_abduction"), -20, 2, 1),
                (f"reba_{side}_upper_arm", col("upper_arm_rotation"), 20, 1, 2),
                (f"reba_{side}_upper_arm", col("shoulder_raise"), 10, 1, 2),
                (f"reba_{side}_lower_arm", col("elbow_flexion"), 60, 2, 1),
                (f"reba_{side}_lower_arm", col("elbow_flexion"), 100, 1, 2),
                (f"reba_{side}_wrist", col("wrist_flexion"), -15, 2, 1),
                (f"reba_{side}_wrist", col("wrist_flexion"), 15, 1, 2),
                (f"reba_{side}_wrist", col("wrist_deviation"), 10, 1, 2),
                (f"reba_{side}_wrist", col("wrist_deviation"), -10, 2, 1),
                (f"reba_{side}_wrist", col("wrist_twist"), 30, 1, 2),
            ]
        else:
            rows += [
                (f"rula_{side}_upper_arm", col("upper_arm_flexion"), -20, 2, 1),
                (f"rula_{side}_upper_arm", col("upper_arm_flexion"), 20, 1, 2),
                (f"rula_{side}_upper_arm", col("upper_arm_flexion"), 45, 2, 3),
                (f"rula_{side}_upper_arm", col("upper_arm_flexion"), 90, 3, 4),
                (f"rula_{side}_upper_arm", col("upper_arm_abduction"), 20, 1, 2),
                (f"rula_{side}_upper_arm", col("shoulder_raise"), 10, 1, 2),
                (f"rula_{side}_lower_arm", col("elbow_flexion"), 60, 2, 1),
                (f"rula_{side}_lower_arm", col("elbow_flexion"), 100, 1, 2),
                (f"rula_{side}_wrist", col("wrist_flexion"), -15, 3, 2),
                (f"rula_{side}_wrist", col("wrist_flexion"), -5, 2, 1),
                (f"rula_{side}_wrist", col("wrist_flexion"), 5, 1, 2),
                (f"rula_{side}_wrist", col("wrist_flexion"), 15, 2, 3),
                (f"rula_{side}_wrist", col("wrist_deviation"), 10, 1, 2),
                (f"rula_{side}_wrist_twist", col("wrist_twist"), 30, 1, 2),
                (f"rula_{side}_wrist_twist", col("wrist_twist"), -30, 2, 1),
            ]
    return rows


KNEES = ("left_knee_flexion", "right_knee_flexion")
ROWS = [
    ("reba_trunk", "trunk_flexion", -20, 3, 2),
    ("reba_trunk", "trunk_flexion", -5, 2, 1),
    ("reba_trunk", "trunk_flexion", 5, 1, 2),
    ("reba_trunk", "trunk_flexion", 20, 2, 3),
    ("reba_trunk", "trunk_flexion", 60, 3, 4),
    ("reba_trunk", "trunk_twist", 10, 1, 2),
    ("reba_trunk", "trunk_twist", -10, 2, 1),
    ("reba_trunk", "trunk_side_bend", 10, 1, 2),
    ("reba_neck", "neck_flexion", -5, 2, 1),
    ("reba_neck", "neck_flexion", 20, 1, 2),
    ("reba_neck", "neck_twist", 10, 1, 2),
    ("reba_neck", "neck_side_bend", -10, 2, 1),
    ("reba_legs", KNEES, 30, 1, 2),
    ("reba_legs", KNEES, 60, 2, 3),
    ("reba_legs", "left_knee_flexion", 60, 2, 3),
    ("reba_legs", "right_knee_flexion", 30, 1, 2),
    ("rula_neck", "neck_flexion", -5, 4, 1),
    ("rula_neck", "neck_flexion", 10, 1, 2),
    ("rula_neck", "neck_flexion", 20, 2, 3),
    ("rula_neck", "neck_twist", 10, 1, 2),
    ("rula_neck", "neck_side_bend", 10, 1, 2),
    ("rula_trunk", "trunk_flexion", -5, 2, 1),
    ("rula_trunk", "trunk_flexion", 5, 1, 2),
    ("rula_trunk", "trunk_flexion", 20, 2, 3),
    ("rula_trunk", "trunk_flexion", 60, 3, 4),
    ("rula_trunk", "trunk_twist", 10, 1, 2),
    ("rula_trunk", "trunk_side_bend", -10, 2, 1),
    *arm_rows("reba"),
    *arm_rows("rula"),
]


def item_at(item: str, columns, value: float, settings: ScoringSettings) -> int:
    names = (columns,) if isinstance(columns, str) else columns
    posture = Posture(neutral_columns(**{name: value for name in names}))
    return int(score_postures(posture, settings)[item][0])


@pytest.mark.parametrize(("item", "columns", "edge", "below", "above"), ROWS,
                         ids=[f"{r[0]}@{r[2]}:{r[1]}" for r in ROWS])
def test_band_edge(item, columns, edge, below, above):
    for mode in ("lower", "upper"):
        settings = ScoringSettings(band_edge=mode)
        assert item_at(item, columns, edge - EPS, settings) == below, (mode, "below")
        assert item_at(item, columns, edge + EPS, settings) == above, (mode, "above")
        on_edge = min(below, above) if mode == "lower" else max(below, above)
        assert item_at(item, columns, edge, settings) == on_edge, (mode, "on the edge")


@pytest.mark.parametrize(("kg", "shock", "reba_load", "rula_force"), [
    (0.0, 0, 0, 0), (1.999, 0, 0, 0), (2.0, 0, 0, 1), (4.999, 0, 0, 1), (5.0, 0, 1, 1),
    (10.0, 0, 1, 1), (10.001, 0, 2, 2), (0.0, 1, 1, 3), (12.0, 1, 3, 3),
])
def test_load_bands_are_read_literally(kg, shock, reba_load, rula_force):
    scores = score_postures(Posture(neutral_columns(load_kg=kg, shock=shock)))
    assert (scores["reba_load"][0], scores["rula_arm_force"][0]) == (reba_load, rula_force)


@pytest.mark.parametrize(("kg", "muscle_use", "rula_force"), [
    (1.0, 1, 0), (2.0, 1, 2), (10.0, 1, 2), (10.001, 0, 2), (10.001, 1, 3), (25.0, 0, 2),
    (25.0, 1, 3),
])
def test_rula_force_for_static_or_repeated_and_intermittent_loads(kg, muscle_use, rula_force):
    """McAtamney & Corlett 1993: >= 10 kg intermittent is 2; 3 only when static or repeated
    (or with shock)."""
    scores = score_postures(Posture(neutral_columns(load_kg=kg, muscle_use=muscle_use)))
    assert scores["rula_arm_force"][0] == rula_force
    assert scores["rula_neck_trunk_legs_force"][0] == rula_force  # absent: the arm group's


def test_rula_static_load_scores_two():
    scores = score_postures(Posture(neutral_columns(load_kg=5.0, muscle_use=1)))
    assert scores["rula_arm_force"][0] == 2
    # Muscle use and force both add to Score C and Score D.
    assert scores["rula_left_score_c"][0] == scores["rula_left_table_a"][0] + 3
    assert scores["rula_score_d"][0] == scores["rula_table_b"][0] + 3


def test_rula_groups_take_their_own_muscle_use_and_load():
    """The worksheet scores muscle use and force/load once for the arm and wrist (Score C) and
    once for neck, trunk and legs (Score D)."""
    arms_only = score_postures(Posture(neutral_columns(
        load_kg=5.0, muscle_use=1, neck_trunk_legs_muscle_use=0, neck_trunk_legs_load_kg=0.0)))
    assert arms_only["rula_arm_force"][0] == 2 and arms_only["rula_neck_trunk_legs_force"][0] == 0
    assert arms_only["rula_left_score_c"][0] == arms_only["rula_left_table_a"][0] + 3
    assert arms_only["rula_score_d"][0] == arms_only["rula_table_b"][0]
    body_only = score_postures(Posture(neutral_columns(neck_trunk_legs_muscle_use=1,
                                                       neck_trunk_legs_load_kg=12.0)))
    assert body_only["rula_neck_trunk_legs_force"][0] == 3
    assert body_only["rula_score_d"][0] == body_only["rula_table_b"][0] + 4
    assert body_only["rula_left_score_c"][0] == body_only["rula_left_table_a"][0]


@pytest.mark.parametrize(("knee", "seated", "legs"), [
    (10.0, 0, 1), (45.0, 0, 2), (90.0, 0, 3), (10.0, 1, 1), (45.0, 1, 1), (90.0, 1, 1)])
def test_reba_legs_when_sitting_score_one_without_the_knee_adjustment(knee, seated, legs):
    scores = score_postures(Posture(neutral_columns(
        left_knee_flexion=knee, right_knee_flexion=knee, seated=seated)))
    assert scores["reba_legs"][0] == legs


def test_action_levels_cover_every_score():
    reba = importlib.import_module("ergohandover.ergonomics.reba")
    rula = importlib.import_module("ergohandover.ergonomics.rula")
    levels = reba.action_level(np.arange(1, 16, dtype=np.int8))
    assert levels.tolist() == [0, 1, 1, 2, 2, 2, 2, 3, 3, 3, 4, 4, 4, 4, 4]
    assert rula.action_level(np.arange(1, 8, dtype=np.int8)).tolist() == [1, 1, 2, 2, 3, 3, 4]


def test_upright_tolerance_setting_moves_the_trunk_edge():
    loose = ScoringSettings(neutral_tolerance_deg=10.0)
    assert item_at("reba_trunk", "trunk_flexion", 8.0, loose) == 1
    assert item_at("reba_trunk", "trunk_flexion", 8.0, ScoringSettings()) == 2
    strict = ScoringSettings(neutral_tolerance_deg=0.0)
    assert item_at("reba_trunk", "trunk_flexion", 0.0, strict) == 1
    assert item_at("reba_trunk", "trunk_flexion", 0.1, strict) == 2
