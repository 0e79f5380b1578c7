"""The derivation of measured handovers' figures (experiments/tools/derive_measured_handovers.py),
on a synthetic data set in the format of Kim et al.'s, made here: the transfer frame, the
receiving hand, the object's place relative to the receiver, the receiver's posture and its
standing neutral and spread come out as the data were made; a handover without a transfer is
dropped with its reason; two runs write the same bytes."""

from __future__ import annotations

import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ergohandover.capture import FORMATS
from ergohandover.capture.placement import place
from ergohandover.study.people.transfer import STEP
from ergohandover.twin.angles import posture_columns
from ergohandover.twin.evaluate import Evaluator, evaluate, joint_angles
from ergohandover.twin.kinematics import KinematicModel
from ergohandover.twin.skeleton import build_skeleton

ROOT = Path(__file__).resolve().parents[1]
TOOL = ROOT / "experiments" / "tools" / "derive_measured_handovers.py"
T, SWITCH = 120, 70
"""Frames of each synthetic handover, and the frame the object passes to the receiver."""
GRIP = np.array([0.11, 0.04, 0.10])  # the object's marker minus the holding hand point
RIGHT_HAND = FORMATS["zed34"].index("right_hand")


@pytest.fixture(scope="module")
def twin():
    """The twin holding the box in front of it: its ZED BODY_34 points and Posture columns."""
    evaluator = Evaluator()
    table = evaluate(np.array([[0.0, 1.0, 0.45]]), evaluator, joints=True)
    state = KinematicModel(build_skeleton(evaluator.body)).forward(joint_angles(table))
    points = place(state, evaluator.body, FORMATS["zed34"], up="z")[0]  # x forward, y left
    return points, posture_columns(state, evaluator.task)


def motion(points: np.ndarray, reaches: bool) -> dict:
    """One handover in the data set's format: the giver stands at the origin facing +x holding
    the object still; the receiver, facing -x, walks past along -x at y = -0.9 in the same
    posture; at SWITCH the object moves with the receiver's right hand (if ``reaches``)."""
    facing_back = np.array([-1.0, -1.0, 1.0])  # turned half round about the vertical
    x = np.linspace(2.0, -0.8, T)
    receiver = points[None] * facing_back + np.column_stack(
        [x, np.full(T, -0.9), np.zeros(T)])[:, None]
    hand = receiver[:, RIGHT_HAND]
    held = hand[SWITCH] + GRIP if reaches else np.array([0.5, 0.5, 1.3])
    obj = np.where((np.arange(T) >= SWITCH)[:, None] & reaches, hand + GRIP, held)
    giver = np.broadcast_to(points - points[RIGHT_HAND] + held - np.array([0.2, 0.07, 0.18]),
                            (T, 34, 3)).copy()
    return {"pose_receiver": receiver, "pose_giver": giver, "pose_object": obj,
            "quat_object": np.tile([1.0, 0.0, 0.0, 0.0], (T, 1))}


@pytest.fixture(scope="module")
def derived(twin, tmp_path_factory):
    points, _ = twin
    data = tmp_path_factory.mktemp("kim") / "data" / "whole_motions"
    data.mkdir(parents=True)
    for name, reaches in (("motion_normal_0", True), ("motion_normal_1", True),
                          ("motion_variation_0", False)):
        with (data / f"{name}.pkl").open("wb") as handle:
            pickle.dump(motion(points, reaches), handle)
    out = []
    for run in ("a", "b"):
        output = data.parent / f"derived_{run}.csv"
        subprocess.run([sys.executable, str(TOOL), str(data.parent), "--output", str(output)],
                       check=True, capture_output=True)
        out.append(output)
    return out


def test_two_runs_write_the_same_bytes(derived):
    assert derived[0].read_bytes() == derived[1].read_bytes()
    assert derived[0].read_text().startswith("# source: Kim et al.")


def test_each_handover_comes_out_as_it_was_made(twin, derived):
    points, truth = twin
    table = pd.read_csv(derived[0], comment="#", keep_default_na=False, na_values=[""])
    used = table[table["dropped"].isna()]
    assert list(used["handover"]) == ["motion_normal_0", "motion_normal_1"]
    assert ((used["transfer_frame"] >= SWITCH - STEP) & (used["transfer_frame"] <= SWITCH + 3)
            ).all()
    assert (used["receiving_hand"] == "right").all()
    assert np.allclose(used["hand_to_object_m"], np.linalg.norm(GRIP), atol=2e-3)
    # The object from the receiver's feet: the twin's own hand, forward of the mid-ankle.
    ankles = (points[FORMATS["zed34"].index("left_ankle")]
              + points[FORMATS["zed34"].index("right_ankle")]) / 2
    marker = points[RIGHT_HAND] + GRIP * np.array([-1.0, -1.0, 1.0])  # GRIP is in the world
    assert np.allclose(used["height_m"], marker[2], atol=2e-3)
    assert np.allclose(used["forward_m"], marker[0] - ankles[0], atol=2e-3)
    # The receiving hand, where the twin's grip is put: the twin's own hand point.
    hand = points[RIGHT_HAND]
    assert np.allclose(used["hand_height_m"], hand[2], atol=2e-3)
    assert np.allclose(used["hand_forward_m"], hand[0] - ankles[0], atol=2e-3)
    assert np.allclose(used["hand_lateral_m"], hand[1] - ankles[1], atol=2e-3)
    zed = FORMATS["zed34"]
    shoulders = (points[zed.index("left_shoulder"), 2] + points[zed.index("right_shoulder"), 2]) / 2
    heels = min(points[zed.index("left_heel"), 2], points[zed.index("right_heel"), 2])
    assert np.allclose(used["shoulder_height_m"], shoulders - heels, atol=2e-3)
    for column in ("trunk_flexion", "neck_flexion", "right_elbow_flexion",
                   "right_upper_arm_flexion", "left_knee_flexion"):
        assert np.allclose(used[column], truth[column][0], atol=0.06), column
    assert used["right_wrist_flexion"].isna().all()  # ZED's rigid hands: unseen
    # The receiver holds one posture throughout: its standing neutral is that posture, and it
    # does not spread around the transfer.
    for column in ("trunk_flexion", "neck_flexion", "right_knee_flexion",
                   "right_elbow_flexion", "left_upper_arm_abduction"):
        assert np.allclose(used[f"neutral_{column}"], used[column], atol=0.06), column
        assert np.allclose(used[f"spread_{column}"], 0.0, atol=0.01), column
    assert (used["reba_lo"] <= used["reba_hi"]).all()


def test_a_handover_without_a_transfer_is_dropped_with_its_reason(derived):
    table = pd.read_csv(derived[0], comment="#", keep_default_na=False, na_values=[""])
    dropped = table[table["dropped"].notna()]
    assert list(dropped["handover"]) == ["motion_variation_0"]
    assert dropped["dropped"].iloc[0].startswith("the object never moves with a receiver's hand")
