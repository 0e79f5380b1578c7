"""Workers the population prior does not know: impaired, stepping, of other proportions; an
IMU suit's measurement error; and the fitted twin's candidates among them."""

from __future__ import annotations

import numpy as np
import pytest

from ergohandover.errors import ConfigError
from ergohandover.robustness.measured_error import MEASURED_ERROR
from ergohandover.robustness.posture_error import ANGLE_COLUMNS
from ergohandover.study.personalise.config import PersonaliseConfig
from ergohandover.study.personalise.measured_answers import Answers, angle_sds, model_of
from ergohandover.study.personalise.unknown_workers import (
    IMPAIRED,
    STEPS_OR_PROPORTIONS,
    UNKNOWN_WORKERS,
    impaired_candidates,
    own_candidate,
    unknown_twin,
)
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.joint_limits import IMPAIRMENTS


def test_each_unknown_worker_is_one_change_of_the_twin():
    twin = Evaluator(BodySpec.from_percentile("p50-female"))
    limits = twin.body.joint_limits_deg()
    for name in IMPAIRMENTS:
        changed = unknown_twin(name, twin)
        narrowed = {k for k, v in changed.body.joint_limits_deg().items() if v != limits[k]}
        assert len(narrowed) == 1 and narrowed <= {j for j, _, _ in IMPAIRMENTS[name]}
        assert changed.task == twin.task and model_of(name) == IMPAIRED
    assert IMPAIRMENTS["shoulder flexion <= 90 deg"][0][2] == 90.0
    assert IMPAIRMENTS["elbow lacks 30 deg of extension"][0][1] == 30.0
    assert IMPAIRMENTS["wrist cannot flex"][0][2] == 0.0
    stepping = unknown_twin("steps toward the box", twin)
    assert stepping.task.stance == "step" and stepping.body == twin.body
    ratio = unknown_twin("fixed-ratio proportions", twin)
    assert ratio.body.proportions == "drillis-contini" and ratio.body.stature_m == \
        twin.body.stature_m
    assert {model_of(n) for n in UNKNOWN_WORKERS} == {IMPAIRED, STEPS_OR_PROPORTIONS}
    assert model_of("in-model") == "in-model" and model_of("gaze off") == "out-of-model"


def test_a_worker_is_never_among_their_own_fitted_twins_candidates():
    twin = Evaluator()
    twins = [("w001", "in-model", twin), ("w001", "wrist cannot flex", twin),
             ("w002", "steps toward the box", twin), ("w002", "wrist cannot flex", twin)]
    names = [n for n, _ in impaired_candidates(twins)]
    assert names == ["w001|wrist cannot flex", "w002|wrist cannot flex"]
    assert own_candidate("w001", "w001") and own_candidate("w001|wrist cannot flex", "w001")
    assert not own_candidate("w0010", "w001") and not own_candidate("w002|x", "w001")


def test_unknown_workers_are_answered_as_the_headline_only():
    part = PersonaliseConfig()
    headline, other = Answers("posture", part.headline_sd), Answers("posture", 0.0)
    assert part.runs_of(headline, "wrist cannot flex") == part.headline_runs
    assert part.runs_of(other, "wrist cannot flex") == 0
    assert part.runs_of(other, "in-model") == part.measured_runs


def test_the_population_is_answered_by_the_published_imu_as_often_as_by_the_headline():
    part = PersonaliseConfig()
    imu, scaled = Answers("imu", 1.0), Answers("imu", 2.0)
    assert part.runs_of(imu, "in-model") == part.headline_runs
    assert part.runs_of(imu, "gaze off") == part.runs_of(scaled, "in-model") == part.measured_runs
    assert part.runs_of(imu, "wrist cannot flex") == 0


def test_imu_answers_are_the_robustness_parts_measured_error_and_weigh_each_angle_by_its_sd():
    imu = Answers("imu", 1.0)
    assert imu.error == MEASURED_ERROR and imu.label == "IMU"
    assert Answers("imu", 1.5).error.sd() == pytest.approx(1.5 * MEASURED_ERROR.sd())
    sds = angle_sds(imu)
    assert sds == dict(zip(ANGLE_COLUMNS, MEASURED_ERROR.sd(), strict=True))
    assert sds["right_upper_arm_flexion"] > sds["trunk_flexion"] > 0
    assert set(angle_sds(Answers("posture", 5.0)).values()) == {5.0}
    assert set(angle_sds(Answers("rater", 0.5)).values()) == {0.0}
    # The answers of an IMU carry its bias: the mean of many measured upper-arm angles.
    drawn = imu.error.errors(20_000, np.random.default_rng(3))
    assert float(np.mean(drawn["right_upper_arm_flexion"])) == pytest.approx(-0.3, abs=0.2)
    with pytest.raises(ConfigError, match="outside the valid range"):
        Answers("imu", -1.0)
