"""The body model fitted to ANSUR II: its table against the survey's data files, bodies built
from a person's measurements against that person, filled-in landmarks against the survey's own
regressions, draws, and the refusals.

The data files are not part of the project: the tests read them from ``ERGOHANDOVER_ANSUR2``
or from ``../shared/data/ansur2`` beside the checkout."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ergohandover.cli.measurements import read_survey_row, survey_measurements
from ergohandover.twin.anthropometry import BodySpec, BodySpecError
from ergohandover.twin.body_model import MEASUREMENTS, SURVEY_SCALE, body_model
from ergohandover.twin.kinematics import KinematicModel
from ergohandover.twin.skeleton import build_skeleton

FILES = {"male": "ANSUR_II_MALE_Public.csv", "female": "ANSUR_II_FEMALE_Public.csv"}


def survey_folder() -> Path:
    env = os.environ.get("ERGOHANDOVER_ANSUR2")
    folder = Path(env) if env else Path(__file__).resolve().parents[1].parent / "shared" / \
        "data" / "ansur2"
    if not all((folder / name).is_file() for name in FILES.values()):
        pytest.skip(f"the ANSUR II public data files are not in {folder} (set "
                    "ERGOHANDOVER_ANSUR2 to their folder)")
    return folder


@pytest.fixture(scope="module")
def survey() -> dict[str, pd.DataFrame]:
    folder = survey_folder()
    return {sex: pd.read_csv(folder / name, encoding="latin-1") for sex, name in FILES.items()}


def in_model_units(table: pd.DataFrame) -> pd.DataFrame:
    columns = list(MEASUREMENTS.values())
    return table[columns].astype(float) / np.array([SURVEY_SCALE[c] for c in columns])


@pytest.mark.parametrize("sex", list(FILES))
def test_the_shipped_table_reproduces_the_data_files(survey, sex):
    model, data = body_model()[sex], in_model_units(survey[sex])
    assert model.n == len(data) == {"male": 4082, "female": 1986}[sex]
    np.testing.assert_allclose(model.mean, data.mean(), atol=6e-6)
    np.testing.assert_allclose(model.sd, data.std(ddof=1), atol=6e-6)
    np.testing.assert_allclose(model.correlation, np.corrcoef(data.to_numpy().T), atol=6e-5)


def test_100_people_built_from_their_measurements_stand_at_their_own_heights(survey):
    rng = np.random.default_rng(26)
    checked = 0
    for sex, table in survey.items():
        for index in rng.choice(len(table), 50, replace=False):
            row = table.iloc[index]
            body = BodySpec.from_measurements(survey_measurements(row.to_dict()), sex)
            fk = KinematicModel(build_skeleton(body)).forward(np.zeros(body_model_nq(body)))
            mm = {column: row[column] / 1000.0 for column in MEASUREMENTS.values()}
            ankle, knee = fk.position("shank")[0], fk.position("thigh")[0]
            hip = fk.position("pelvis")[0]
            shoulder = fk.position("right_upper_arm")[0]
            elbow, wrist = fk.position("right_forearm")[0], fk.position("right_hand")[0]
            # Joint heights of the standing twin against the person's own landmarks [m].
            assert ankle[2] == pytest.approx(mm["lateralmalleolusheight"], abs=0.01)
            assert knee[2] == pytest.approx(mm["lateralfemoralepicondyleheight"], abs=0.01)
            assert hip[2] == pytest.approx(mm["trochanterionheight"], abs=0.01)
            assert shoulder[2] == pytest.approx(mm["acromialheight"], abs=0.01)
            assert elbow[2] == pytest.approx(mm["acromialheight"] - mm["acromionradialelength"],
                                             abs=0.01)
            assert wrist[2] == pytest.approx(mm["wristheight"], abs=0.01)
            assert np.linalg.norm(shoulder - elbow) == pytest.approx(
                mm["acromionradialelength"], abs=0.01)
            assert body.elbow_height_m == pytest.approx(
                mm["acromialheight"] - mm["shoulderelbowlength"], abs=0.01)
            assert body.stature_m == pytest.approx(mm["stature"], abs=0.001)
            checked += 1
    assert checked == 100


def body_model_nq(body: BodySpec) -> int:
    return KinematicModel(build_skeleton(body)).nq


@pytest.mark.parametrize("sex", list(FILES))
def test_filled_in_landmarks_are_the_surveys_own_regression_on_stature(survey, sex):
    data = in_model_units(survey[sex])
    stature = data["stature"].to_numpy()
    for column, name in (("acromialheight", "shoulder_height_m"),
                         ("trochanterionheight", "hip_height_m"),
                         ("wristheight", "wrist_height_m")):
        slope, intercept = np.polyfit(stature, data[column].to_numpy(), 1)
        for height in (1.55, 1.75, 1.90):
            body = BodySpec.from_measurements({"stature_m": height}, sex)
            assert body.landmarks()[name] == pytest.approx(intercept + slope * height,
                                                           abs=0.001), (column, height)


def test_a_given_landmark_is_kept_and_moves_its_neighbours():
    plain = BodySpec()
    low = BodySpec.from_measurements({"stature_m": plain.stature_m, "mass_kg": plain.mass_kg,
                                      "elbow_height_m": plain.elbow_height_m - 0.035})
    assert low.elbow_height_m == pytest.approx(plain.elbow_height_m - 0.035, abs=1e-6)
    # A lower elbow at the same stature comes with a lower shoulder and a lower wrist.
    assert low.shoulder_height_m < plain.shoulder_height_m
    assert low.landmarks()["wrist_height_m"] < plain.landmarks()["wrist_height_m"]
    assert low.stature_m == plain.stature_m


def test_sex_matters_beyond_stature():
    man = BodySpec.from_measurements({"stature_m": 1.70}, "male")
    woman = BodySpec.from_measurements({"stature_m": 1.70}, "female")
    # At the same stature, women in the survey have longer legs and narrower shoulders.
    assert woman.landmarks()["hip_height_m"] > man.landmarks()["hip_height_m"] + 0.01
    assert woman.landmarks()["shoulder_breadth_m"] < man.landmarks()["shoulder_breadth_m"] - 0.02


def test_the_same_seed_draws_the_same_bodies():
    a = BodySpec.sample(5, "female", np.random.default_rng(3))
    b = BodySpec.sample(5, "female", np.random.default_rng(3))
    c = BodySpec.sample(5, "female", np.random.default_rng(4))
    assert a == b and a != c
    assert all(dict(p.measurements)["shoulder_height_m"] > p.elbow_height_m for p in a)


def test_a_survey_row_is_read_in_the_surveys_units(tmp_path, survey):
    path = tmp_path / "one.csv"
    survey["female"].iloc[[7]].to_csv(path, index=False)
    values, sex = read_survey_row(path)
    assert sex == "female"
    assert values["stature_m"] == survey["female"]["stature"].iloc[7] / 1000.0
    assert values["mass_kg"] == survey["female"]["weightkg"].iloc[7] / 10.0


@pytest.mark.parametrize(("given", "message"), [
    ({"elbow_height_m": -0.5}, r"^elbow_height_m = -0.5 is outside the valid range"),
    ({"stature_m": 1.75, "shoulder_height_m": 1.15, "elbow_height_m": 1.2},
     r"^elbow_height_m = 1.200 m is not below shoulder_height_m = 1.150 m"),
    ({"stature_m": 1.75, "knee_height_m": 0.64, "hip_height_m": 0.63},
     r"^knee_height_m = 0.640 m is not below hip_height_m = 0.630 m"),
    ({"elbow_height": 1.0}, r"^elbow_height is not a known measurement"),
    ({"shoulder_height_m": 1.45, "shoulder_elbow_length_m": 0.36, "elbow_height_m": 1.0},
     r"disagrees with the other measurements"),
    ({"stature_m": 2.5}, r"^stature_m = 2.5 is outside the valid range 1.40-2.10 m"),
])
def test_bad_measurements_are_one_line_errors(given, message):
    with pytest.raises(BodySpecError, match=message) as caught:
        BodySpec.from_measurements(given)
    assert "\n" not in str(caught.value)


def test_the_earlier_ratios_take_no_measurements():
    with pytest.raises(BodySpecError, match="takes no measurements"):
        BodySpec(measurements=(("elbow_height_m", 1.0),), proportions="drillis-contini")
