"""The capture layer: the twin's own postures, placed as each keypoint format places its joints,
come back as the twin's angles; moved, turned, scaled and mirrored bodies give the same (or
mirrored) angles; and what a format cannot see becomes an interval that holds the true score."""

from __future__ import annotations

import dataclasses
import importlib

import numpy as np
import pytest
from twin_postures import random_twin_postures

from ergohandover.capture import FORMATS, capture, capture_scores, keypoint_format
from ergohandover.capture.angles import clavicle_slope_deg, measure
from ergohandover.capture.checks import check_keypoints
from ergohandover.capture.formats import SIDES, FormatError, z_up
from ergohandover.capture.placement import place, to_axes
from ergohandover.capture.readers import Keypoints
from ergohandover.capture.unseen import items_read, plausible_ranges
from ergohandover.ergonomics import Posture, ScoringSettings, score_postures
from ergohandover.ergonomics.posture import COLUMN_BY_NAME, POSTURE_COLUMNS
from ergohandover.ergonomics.reba import items as reba_items
from ergohandover.ergonomics.rula import items as rula_items
from ergohandover.twin.anthropometry import BodySpec

EVERYTHING = dataclasses.replace(FORMATS["zed34"], unseen=())
"""ZED BODY_34's points, everything they could show measured (the SDK holds some rigid)."""
EXACT = ("h36m17", "zed34", "smpl24")
"""Formats with a spine point and a neck base: their trunk is the twin's thorax."""
FACE = ("coco17", "mediapipe33")
"""Formats whose trunk runs from the mid-hip to the mid-shoulder point."""
EXACT_COLUMNS = ("knee_flexion", "elbow_flexion", "wrist_flexion", "wrist_deviation")
"""Columns every format measures as the twin does: from the limb's own points."""
FACE_TOLERANCE_DEG = {"trunk_flexion": 10.0, "trunk_side_bend": 7.0, "trunk_twist": 5.0,
                      "neck_flexion": 11.0, "neck_side_bend": 9.0, "neck_twist": 5.0,
                      "upper_arm_abduction": 8.0}
"""How far the mid-hip to mid-shoulder trunk of COCO and MediaPipe may lie from the twin's
thorax, and what it moves (the round trip's largest errors on these postures, rounded up)."""


@pytest.fixture(scope="module")
def postures():
    return random_twin_postures(600, 1)


def task_of(truth: dict[str, np.ndarray]) -> dict[str, float]:
    """The task factors of the twin's postures, which keypoints cannot show."""
    return {name: float(truth[name][0]) for name in ("load_kg", "coupling", "activity")}


def angle_error(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs((a - b + 180.0) % 360.0 - 180.0)


@pytest.mark.parametrize("name", FORMATS)
def test_the_twins_postures_come_back_as_its_angles(postures, name):
    body, state, truth = postures
    fmt = FORMATS[name]
    got = measure(place(state, body, fmt), fmt)
    for column, values in got.items():
        seen = np.isfinite(values)
        if not seen.any():
            continue
        error = angle_error(values[seen], truth[column][seen])
        if column.endswith(("across_midline", "hands_above_neck")):
            continue  # flags: below
        if name in EXACT or column.split("_", 1)[1] in EXACT_COLUMNS:
            assert error.max() < 1e-6, (name, column, error.max())
        else:
            bare = column.removeprefix("left_").removeprefix("right_")
            assert np.percentile(error, 95) < FACE_TOLERANCE_DEG.get(bare, 12.0), (
                name, column, np.percentile(error, 95))


@pytest.mark.parametrize("name", FORMATS)
def test_a_format_sees_what_its_points_show(postures, name):
    body, state, _ = postures
    fmt = FORMATS[name]
    got = measure(place(state, body, fmt), fmt)
    seen = {c for c, v in got.items() if np.isfinite(v).any()}
    hands = "left_hand" in fmt.landmarks and ("left_thumb" in fmt.landmarks
                                                or "left_index" in fmt.landmarks)
    assert ("left_wrist_flexion" in seen) == (hands and "left_wrist_flexion" not in fmt.unseen)
    assert ("neck_twist" in seen) == ("left_ear" in fmt.landmarks)
    clavicle = ("neck_base" in fmt.landmarks or "left_clavicle" in fmt.landmarks) and (
        "left_shoulder_raise" not in fmt.unseen)
    assert ("left_shoulder_raise" in seen) == clavicle
    assert ("left_upper_arm_rotation" in seen) == clavicle
    assert not seen & set(fmt.unseen)
    for column in ("trunk_flexion", "left_knee_flexion", "right_elbow_flexion",
                   "right_upper_arm_flexion"):
        assert np.isfinite(got[column]).all()


def test_rotation_is_unseen_where_the_elbow_is_straight(postures):
    body, state, truth = postures
    fmt = EVERYTHING
    got = measure(place(state, body, fmt), fmt)
    straight = truth["left_elbow_flexion"] < 14.9
    bent = truth["left_elbow_flexion"] > 15.1
    assert straight.any() and bent.any()
    assert np.isnan(got["left_upper_arm_rotation"][straight]).all()
    assert np.isnan(got["left_wrist_twist"][straight]).all()
    assert np.isfinite(got["left_upper_arm_rotation"][bent]).all()
    # Flexion and deviation do not depend on the forearm's roll: seen either way.
    np.testing.assert_allclose(got["left_wrist_flexion"], truth["left_wrist_flexion"],
                               atol=1e-6)


@pytest.mark.parametrize("name", FORMATS)
def test_a_moved_turned_and_scaled_body_gives_the_same_angles(postures, name):
    body, state, _ = postures
    fmt = FORMATS[name]
    points = place(state, body, fmt, up="z")
    rng = np.random.default_rng(4)
    turn = rng.uniform(-np.pi, np.pi)
    c, s = np.cos(turn), np.sin(turn)
    about_up = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    moved = 1.7 * points @ about_up.T + np.array([3.0, -2.0, 0.5])
    for up in ("z", "-x", "y"):
        written = to_axes(moved, up)
        a, b = measure(points, fmt, "z"), measure(written, fmt, up)
        for column in a:
            if column.endswith(("across_midline", "hands_above_neck")):
                continue  # flags are in metres: a scaled body is another body
            both = np.isfinite(a[column])
            assert (np.isfinite(b[column]) == both).all(), column
            if both.any():
                assert angle_error(a[column][both], b[column][both]).max() < 1e-6, (column, up)


@pytest.mark.parametrize("name", FORMATS)
def test_a_mirrored_body_gives_mirrored_angles(postures, name):
    body, state, _ = postures
    fmt = FORMATS[name]
    points = place(state, body, fmt, up="z")
    swapped = [fmt.index(j.replace("left", "§").replace("right", "left").replace("§", "right"))
               for j in fmt.joints]
    mirror = points[:, swapped] * np.array([1.0, -1.0, 1.0])
    a, b = measure(points, fmt, "z"), measure(mirror, fmt, "z")
    for column in a:
        other = column.replace("left", "§").replace("right", "left").replace("§", "right")
        sign = -1.0 if column in ("trunk_side_bend", "trunk_twist", "neck_side_bend",
                                  "neck_twist") else 1.0
        both = np.isfinite(a[column])
        assert (np.isfinite(b[other]) == both).all(), column
        if both.any():
            assert angle_error(sign * a[column][both], b[other][both]).max() < 1e-6, column


def test_another_body_needs_its_own_clavicle_slope():
    """Shoulder raise is the clavicle's elevation above its slope at rest, a body's own."""
    body, state, truth = random_twin_postures(200, 2, BodySpec.from_percentile("p5-female"))
    fmt = EVERYTHING
    got = measure(place(state, body, fmt), fmt, neutral_clavicle_deg=clavicle_slope_deg(body))
    np.testing.assert_allclose(got["left_shoulder_raise"], truth["left_shoulder_raise"],
                               atol=1e-6)
    default = measure(place(state, body, fmt), fmt)
    assert angle_error(default["left_shoulder_raise"], truth["left_shoulder_raise"]).min() > 1


@pytest.mark.parametrize("name", FORMATS)
def test_unseen_columns_give_intervals_that_hold_the_true_score(postures, name):
    body, state, truth = postures
    fmt = FORMATS[name]
    captured = capture(place(state, body, fmt), fmt, assume=task_of(truth))
    scores = capture_scores(captured)
    true = score_postures(Posture(truth))
    measured_rows = ~captured.unseen.any(axis=1)
    for score in ("reba", "rula", "paper_postural"):
        lo, hi, value = scores[f"{score}_lo"], scores[f"{score}_hi"], scores[score]
        assert (lo <= hi).all()
        assert np.array_equal(np.isfinite(value), lo == hi)
        if name in EXACT:  # every measured column is the twin's: the interval holds the truth
            assert ((lo <= true[score]) & (true[score] <= hi)).all(), score
        assert (np.isfinite(value[measured_rows])).all()


def test_a_missing_point_widens_the_scores_it_decides_and_no_other():
    body, state, truth = random_twin_postures(300, 3)
    fmt = FORMATS["zed34"]
    points = place(state, body, fmt)
    whole = capture(points, fmt, assume=task_of(truth))
    points[::2, fmt.index("left_elbow")] = np.nan  # every other frame loses its left elbow
    captured = capture(points, fmt, assume=task_of(truth))
    lost = captured.unseen & ~whole.unseen
    names = [POSTURE_COLUMNS[i] for i in np.flatnonzero(lost.any(axis=0))]
    assert "left_elbow_flexion" in names and "left_upper_arm_flexion" in names
    assert all(n.startswith("left_") for n in names)
    assert not lost[1::2].any()
    scores = capture_scores(captured)
    true = score_postures(Posture(truth))
    for score in ("reba", "rula", "paper_postural"):
        assert ((scores[f"{score}_lo"] <= true[score])
                & (true[score] <= scores[f"{score}_hi"])).all()
    assert (scores["reba_hi"][::2] - scores["reba_lo"][::2]).mean() > 0


def test_intervals_are_the_extremes_the_prior_reaches():
    """Sampling the unseen columns never leaves the interval, and over many draws reaches both
    ends; the interval is not wider than the scores the ranges allow."""
    body, state, _ = random_twin_postures(60, 5)
    fmt = FORMATS["h36m17"]
    captured = capture(place(state, body, fmt), fmt)
    scores = capture_scores(captured, mode="prior", rng=np.random.default_rng(0), draws=4000)
    for score in ("reba", "rula", "paper_postural"):
        share = scores[f"{score}_probabilities"]
        np.testing.assert_allclose(share.sum(axis=1), 1.0)
        values = np.arange(share.shape[1])
        low = np.array([values[row > 0].min() for row in share])
        high = np.array([values[row > 0].max() for row in share])
        assert (low >= scores[f"{score}_lo"]).all() and (high <= scores[f"{score}_hi"]).all()
        assert (low == scores[f"{score}_lo"]).mean() > 0.9
        assert (high == scores[f"{score}_hi"]).mean() > 0.9


def test_an_assumed_column_is_no_longer_unseen():
    body, state, _ = random_twin_postures(50, 6)
    fmt = FORMATS["h36m17"]
    assume = {f"{side}_{part}": 0.0 for side in SIDES
              for part in ("wrist_flexion", "wrist_deviation", "wrist_twist")}
    captured = capture(place(state, body, fmt), fmt, assume={**assume, "neck_twist": 0.0,
                                                             "load_kg": 7.0})
    names = {POSTURE_COLUMNS[i] for i in np.flatnonzero(captured.unseen.any(axis=0))}
    assert names <= {"left_upper_arm_rotation", "right_upper_arm_rotation", "hands_above_neck",
                     "left_arm_across_midline", "right_arm_across_midline"}
    assert (captured.columns["load_kg"] == 7.0).all()
    assert (captured.columns["neck_trunk_legs_load_kg"] == 7.0).all()  # the same load


def test_tables_never_fall_as_an_item_rises():
    """What makes the intervals exact: Tables A, B and C of REBA and RULA are non-decreasing
    in every item."""
    for name in ("reba", "rula"):
        module = importlib.import_module(f"ergohandover.ergonomics.{name}")
        for table in (module.TABLE_A, module.TABLE_B, module.TABLE_C):
            for axis in range(table.ndim):
                assert (np.diff(table, axis=axis) >= 0).all(), (name, axis)


def test_plausible_ranges_come_from_the_twins_joint_ranges():
    ranges = plausible_ranges()
    limits = BodySpec().joint_limits_deg()
    assert ranges["left_wrist_flexion"] == limits["left_wrist_flexion"]
    assert ranges["right_upper_arm_rotation"] == limits["right_shoulder_rotation"]
    assert ranges["left_wrist_twist"] == limits["left_forearm_pronation"]
    assert ranges["hands_above_neck"] == (0.0, 1.0)
    assert all(lo <= 0.0 <= hi for lo, hi in ranges.values())


def test_formats_and_axes_are_refused_by_name():
    with pytest.raises(FormatError, match="format 'openpose' is not known"):
        keypoint_format("openpose")
    with pytest.raises(FormatError, match="up axis 'up' is not allowed"):
        z_up("up")
    body, state, _ = random_twin_postures(2, 9)
    fmt = FORMATS["h36m17"]
    keypoints = Keypoints(np.array([1, 2]), place(state, body, fmt), fmt)
    with pytest.raises(FormatError, match="up axis 'q' is not allowed"):
        check_keypoints(keypoints, "q", "error", "two.csv")  # before anything is checked
    for up in ("x", "-x", "y", "-y", "z", "-z"):
        order, sign = z_up(up)
        turned = np.eye(3)[order] * np.array([[1.0], [1.0], [sign]])
        assert np.isclose(np.linalg.det(turned), 1.0)  # right-handed either way


@pytest.mark.parametrize("name", FACE)
def test_away_from_band_edges_a_format_of_its_own_trunk_gives_the_twins_item_scores(
        postures, name):
    """Where every angle is within the format's tolerance of the twin's and further than that
    from its band edges, COCO-17's and MediaPipe-33's item scores are the twin's (an item that
    reads an unseen column is an interval's business: above)."""
    body, state, truth = postures
    fmt = FORMATS[name]
    captured = capture(place(state, body, fmt), fmt, assume=task_of(truth))
    settings = ScoringSettings()

    def items(columns):
        return {**reba_items(Posture(columns), settings), **rula_items(Posture(columns),
                                                                       settings)}

    want, got = items(truth), items(captured.columns)
    reads = items_read(settings)
    checked = 0
    for item, values in want.items():
        ok = np.ones(len(values), dtype=bool)
        for column in reads[item]:
            at = POSTURE_COLUMNS.index(column)
            if COLUMN_BY_NAME[column].kind != "angle":
                ok &= captured.columns[column] == truth[column]
                continue
            bare = column.removeprefix("left_").removeprefix("right_")
            tol = 1e-6 if bare in EXACT_COLUMNS else FACE_TOLERANCE_DEG.get(bare, 12.0)
            ok &= ~captured.unseen[:, at]
            ok &= angle_error(captured.columns[column], truth[column]) <= tol
            for step in np.linspace(-tol, tol, 9):  # every band the error could reach
                moved = items({**truth, column: np.clip(truth[column] + step, -180, 180)})
                ok &= moved[item] == values
        assert (got[item][ok] == values[ok]).all(), item
        checked += ok.sum()
    assert checked > 1000  # enough postures away from every edge to say something
