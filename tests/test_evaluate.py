"""The twin's postures obey the physics a person's would, and evaluate() is deterministic."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ergohandover.ergonomics import SCORE_COLUMNS
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import (
    EVALUATION_COLUMNS,
    EvaluationError,
    Evaluator,
    evaluate,
    evaluate_arrays,
    evaluate_stream,
    posture_solver,
)
from ergohandover.twin.solver import SolverSettings
from ergohandover.twin.task import Boundary, TaskSpec, TaskSpecError

BODY = BodySpec()
SEG = BODY.segments()
ELBOW_HEIGHT = SEG.shoulder_height - SEG.upper_arm_length


def one(x: float, y: float, z: float, **parts) -> pd.Series:
    """The row of one location; ``parts``: the Evaluator's (body, task, ...)."""
    return evaluate(np.array([[x, y, z]]), Evaluator(**parts)).iloc[0]


def test_a_box_at_knee_height_makes_the_worker_stoop_or_squat():
    row = one(0.0, SEG.knee_height, 0.40)
    assert row["feasible"] == 1
    assert row["trunk_flexion"] > 20 or row["left_knee_flexion"] > 30


def test_a_box_at_elbow_height_is_held_upright_with_elbows_bent():
    row = one(0.0, ELBOW_HEIGHT, 0.35)
    assert row["feasible"] == 1
    assert abs(row["trunk_flexion"]) <= 10
    for side in ("left", "right"):
        assert 60 <= row[f"{side}_elbow_flexion"] <= 100


def test_a_box_above_the_head_puts_the_hands_above_the_neck():
    row = one(0.0, BODY.stature_m + 0.10, 0.35)
    assert row["feasible"] == 1 and row["hands_above_neck"] == 1
    assert one(0.0, ELBOW_HEIGHT, 0.35)["hands_above_neck"] == 0


@pytest.mark.slow
def test_gaze_on_bends_the_neck_toward_a_low_box_and_gaze_off_does_not():
    # A box low and close, 0.95 m high (the paper-code grid's score-4 region without gaze):
    # keeping it within the eyes' 25-degree cone flexes the neck past the paper's 20 degrees.
    looking = one(0.0, 0.95, 0.33)
    ignoring = one(0.0, 0.95, 0.33, task=TaskSpec(gaze="off"))
    assert looking["feasible"] == 1 and ignoring["feasible"] == 1
    assert looking["neck_flexion"] > 20 and abs(ignoring["neck_flexion"]) < 5
    assert ignoring["paper_postural"] == 4 and looking["paper_postural"] > 4
    # Where the box is in view anyway, the gaze task changes nothing.
    high = (0.0, BODY.stature_m - 0.30, 0.40)
    assert one(*high)["neck_flexion"] == pytest.approx(
        one(*high, task=TaskSpec(gaze="off"))["neck_flexion"], abs=0.5)


def test_a_gaze_setting_outside_on_off_is_one_line_error():
    with pytest.raises(TaskSpecError, match=r"^gaze = 'yes' is not allowed \(use 'on' or 'off'\)$"):
        TaskSpec(gaze="yes")


ARM_ANGLES = ("upper_arm_flexion", "upper_arm_abduction", "upper_arm_rotation",
              "shoulder_raise", "elbow_flexion", "wrist_flexion", "wrist_deviation",
              "wrist_twist")


def test_centred_boxes_give_equal_left_and_right_angles():
    rng = np.random.default_rng(0)
    points = Boundary.paper_code().sample(40, rng)
    points[:, 0] = 0.0
    table = evaluate(points)
    for name in ARM_ANGLES:
        diff = (table[f"left_{name}"] - table[f"right_{name}"]).abs().max()
        assert diff < 0.5, name
    assert (table["trunk_twist"].abs() < 0.5).all()
    assert (table["trunk_side_bend"].abs() < 0.5).all()


def test_mirroring_x_mirrors_left_and_right():
    rng = np.random.default_rng(1)
    points = Boundary.paper_code().sample(30, rng)
    table = evaluate(points)
    mirrored = evaluate(points * np.array([-1.0, 1.0, 1.0]))
    for name in ARM_ANGLES:
        np.testing.assert_allclose(mirrored[f"left_{name}"], table[f"right_{name}"], atol=0.5,
                                   err_msg=name)
    np.testing.assert_allclose(mirrored["trunk_twist"], -table["trunk_twist"], atol=0.5)
    np.testing.assert_array_equal(mirrored["reba"], table["reba"])


def test_every_feasible_posture_keeps_the_centre_of_mass_over_the_feet():
    evaluator = Evaluator()
    solver = posture_solver(evaluator)
    points = Boundary.from_body(BODY, TaskSpec()).sample(400, np.random.default_rng(2))
    table = evaluate(points)
    com = solver.solve(points).com
    x0, x1, y0, y1 = solver.support
    inside = (com[:, 0] >= x0) & (com[:, 0] <= x1) & (com[:, 1] >= y0) & (com[:, 1] <= y1)
    feasible = table["feasible"].to_numpy() == 1
    assert feasible.mean() > 0.9
    assert inside[feasible].all()


@pytest.mark.parametrize(("point", "kwargs", "reason"), [
    ((0.0, 1.20, 1.10), {}, "hand_miss"),  # beyond arm's reach
    ((0.0, 1.00, 0.15), {}, "box_collision"),  # the box inside the chest
    ((0.0, 0.80, 0.60), {"settings": SolverSettings(balance=0.0)}, "unbalanced"),
])
@pytest.mark.slow
def test_each_infeasibility_has_its_reason_and_no_scores(point, kwargs, reason):
    row = one(*point, **kwargs)
    assert row["feasible"] == 0
    assert reason in row["reason"].split(";")
    assert all(pd.isna(row[c]) for c in SCORE_COLUMNS)


def test_feasible_rows_have_a_hand_on_each_handle_and_every_score():
    table = evaluate(Boundary.paper_code().sample(100, np.random.default_rng(3)))
    feasible = table[table["feasible"] == 1]
    assert (feasible["hand_error_m"] <= 0.01).all() and (feasible["reason"] == "").all()
    assert feasible[list(SCORE_COLUMNS)].notna().all().all()
    assert list(table.columns) == list(EVALUATION_COLUMNS)


def test_rows_are_bit_identical_whatever_the_order_batching_or_workers():
    points = Boundary.paper_code().sample(1200, np.random.default_rng(4))
    table = evaluate(points)
    order = np.random.default_rng(5).permutation(len(points))
    shuffled = evaluate(points[order], workers=2)
    pd.testing.assert_frame_equal(shuffled.reset_index(drop=True),
                                  table.iloc[order].reset_index(drop=True), check_exact=True)
    alone = evaluate(points[order[:3]])
    pd.testing.assert_frame_equal(alone, table.iloc[order[:3]].reset_index(drop=True),
                                  check_exact=True)


def test_the_stream_yields_each_batch_in_order_as_evaluate_arrays_would():
    points = Boundary.paper_code().sample(700, np.random.default_rng(6))
    sizes = (250, 1, 449)  # uneven batches, one of a single location
    batches = np.split(points, np.cumsum(sizes)[:-1])
    columns = ("flags", "paper_postural", "trunk_flexion")
    whole = evaluate_arrays(points, columns=columns)
    streamed = list(evaluate_stream(batches, columns=columns, workers=2))
    assert [len(part["flags"]) for part in streamed] == list(sizes)
    for c in columns:
        np.testing.assert_array_equal(np.concatenate([part[c] for part in streamed]), whole[c])
    with pytest.raises(EvaluationError, match="not finite"):
        list(evaluate_stream([points[:2], np.array([[0.0, np.nan, 0.4]])]))


def test_a_smaller_worker_reaches_less_far():
    small = BodySpec.from_percentile("p5-female")
    point = (0.0, 1.0, 0.92)
    assert one(*point)["feasible"] == 1
    assert one(*point, body=small)["reason"] == "hand_miss"


def test_pybullet_ik_converges_on_reachable_locations():
    table = evaluate(np.array([[0.0, ELBOW_HEIGHT, 0.35], [0.1, 1.2, 0.45]]),
                     Evaluator(solver="pybullet"))
    assert (table["hand_error_m"] < 0.01).all()


def test_bad_locations_are_rejected():
    with pytest.raises(EvaluationError, match="shape"):
        evaluate(np.zeros((3, 2)))
    with pytest.raises(EvaluationError, match="row 2 is not finite"):
        evaluate(np.array([[0, 1, 0.4], [0, np.nan, 0.4]]))
    with pytest.raises(EvaluationError, match="solver = 'unity'"):
        evaluate(np.zeros((1, 3)), Evaluator(solver="unity"))
    with pytest.raises(EvaluationError, match="is not an Evaluator"):
        evaluate(np.zeros((1, 3)), BodySpec())
