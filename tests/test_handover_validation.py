"""The twin beside measured human handovers: the shipped reference figures, the frame they are
put into, the receiver twin's size, and the comparison table."""

from __future__ import annotations

import numpy as np
import pytest

from ergohandover.landscape.store import landscape_of
from ergohandover.study.config import StudyConfig
from ergohandover.study.shared import grid_of
from ergohandover.study.validation.handovers import (
    handover_table,
    placements,
    receiver_twin,
    reference,
)


def test_the_reference_carries_its_source_and_licence():
    data = reference()
    source = data["source"]
    assert "10.1109/RO-MAN57019.2023.10309537" in source["doi"]
    assert source["licence"].startswith("MIT")
    assert len(data["handovers"]) >= 1
    for handover in data["handovers"]:
        # The object changes hands between the taker's first grip and the giver's release.
        bounds = handover["frames_bounds"]
        assert bounds["taker_onset"] <= handover["frame"] <= bounds["giver_release"]
        # People take it in front of them, between elbow and hip height.
        obj = handover["object"]
        assert 0.3 < obj["forward_of_hip_m"] < 0.9
        assert -0.4 < obj["above_elbow_m"] < 0.1


def test_a_handover_is_put_in_the_worker_frame():
    handover = {"hand": "right", "positions": {
        "baton": {"forward_m": 0.6, "left_m": 0.1, "height_m": 1.1},
        "wrist_R": {"forward_m": 0.45, "left_m": -0.05, "height_m": 1.05}}}
    points = placements(handover)
    # Worker frame: x to the right (so the receiver's left is -x), y up, z forward.
    np.testing.assert_allclose(points["object"], [-0.1, 1.1, 0.6])
    np.testing.assert_allclose(points["hand"], [0.0, 1.05, 0.45])
    handover["positions"]["wrist_R"] = {"forward_m": None, "left_m": None, "height_m": None}
    assert placements(handover)["hand"] is None


def test_the_receiver_twin_is_sized_like_the_participants():
    data = reference()
    twin = receiver_twin(StudyConfig().task(), data)
    stature = data["source"]["metadata"]["stature_cm"]["mean"] / 100.0
    assert twin.body.sex == "male" and twin.body.stature_m == pytest.approx(stature, abs=5e-4)
    assert 0.60 < twin.body.elbow_height_m / twin.body.stature_m < 0.63


@pytest.mark.slow
def test_the_table_sets_the_twins_angles_and_scores_beside_the_receivers():
    config = StudyConfig()
    twin = receiver_twin(config.task())
    found = landscape_of(twin, grid_of(twin, "paper-code", 0.04), progress=False)
    table = handover_table(twin, found)
    angles = table[table["measured"].notna()]
    assert set(angles["quantity"]) >= {"trunk_inclination_deg", "upper_arm_elevation_trunk_deg"}
    assert (angles["difference"] == (angles["twin"] - angles["measured"]).round(1)).all()
    # Holding the box where people held the object, the twin's upper arm is raised as theirs.
    arm = angles[(angles["quantity"] == "upper_arm_elevation_trunk_deg")
                 & (angles["placement"] == "object")]
    assert (arm["difference"].abs() < 10).all()
    scores = table[table["measured"].isna()]
    assert set(scores["quantity"]) == {"paper_postural_score", "reba_score", "rula_score"}
    feasible = scores[(scores["feasible"] == 1) & (scores["placement"] != "baton")]
    assert (feasible["twin"] >= feasible["twin_optimum"]).all()
    assert feasible["share_better"].between(0, 1).all()
    # The baton in one hand is another task: no optimum of the box's landscape beside it.
    baton = table[table["placement"] == "baton"]
    assert len(baton) and baton["twin_optimum"].isna().all()
    assert set(baton["hand"]) <= {"right", "left"}
