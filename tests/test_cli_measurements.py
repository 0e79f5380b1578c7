"""A worker's own measurements on the command line: ``--elbow-height``, ``--arm-length``,
``--shoulder-height``, ``--measurements CSV`` and ``--proportions``, on ``evaluate`` and
``sweep``; bad ones are one line and exit 2, and nothing is written."""

from __future__ import annotations

import pandas as pd
import pytest
from cli_run import run_cli

from ergohandover.cli import main
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator, evaluate


@pytest.fixture
def points(tmp_path):
    path = tmp_path / "points.csv"
    path.write_text("x,y,z\n0,1.00,0.40\n")
    return path


def test_an_elbow_height_sizes_the_worker_that_evaluate_solves(points, tmp_path):
    out = tmp_path / "low_elbow.csv"
    assert main(["evaluate", "--points", str(points), "--output", str(out),
                 "--elbow-height", "1.02"]) == 0
    body = BodySpec.from_measurements({"stature_m": BodySpec().stature_m,
                                       "mass_kg": BodySpec().mass_kg, "elbow_height_m": 1.02})
    expected = evaluate(pd.read_csv(points).to_numpy(float), Evaluator(body))
    table = pd.read_csv(out, keep_default_na=False)
    assert table["paper_postural"].tolist() == expected["paper_postural"].tolist()
    assert table["right_elbow_flexion"].to_numpy() == pytest.approx(
        expected["right_elbow_flexion"].to_numpy(), abs=1e-6)


def test_a_survey_row_gives_the_worker_and_its_sex(points, tmp_path):
    row = tmp_path / "person.csv"
    row.write_text("stature,weightkg,acromialheight,wristheight,Gender\n1652,612,1351,805,Female\n")
    out = tmp_path / "person_eval.csv"
    assert main(["evaluate", "--points", str(points), "--output", str(out),
                 "--measurements", str(row)]) == 0
    body = BodySpec.from_measurements({"stature_m": 1.652, "mass_kg": 61.2,
                                       "shoulder_height_m": 1.351, "wrist_height_m": 0.805},
                                      "female")
    expected = evaluate(pd.read_csv(points).to_numpy(float), Evaluator(body))
    assert pd.read_csv(out)["reba"].tolist() == expected["reba"].tolist()


@pytest.mark.parametrize(("flags", "message"), [
    (["--elbow-height", "-1"], "--elbow-height -1: must be > 0 m"),
    (["--elbow-height", "0.3"], "--elbow-height 0.3: outside the valid range 0.78-1.37 m"),
    (["--elbow-height", "1.2", "--shoulder-height", "1.15"],
     "--elbow-height 1.200: not below --shoulder-height 1.150"),
    (["--arm-length", "0.6", "--proportions", "drillis-contini"],
     "--proportions drillis-contini takes no measurements"),
])
def test_bad_measurements_are_one_line_and_exit_2(points, tmp_path, flags, message):
    out = tmp_path / "never.csv"
    for command in (["evaluate", "--points", str(points)], ["sweep", "--step", "0.05"]):
        result = run_cli(*command, "--output", str(out), *flags)
        assert result.returncode == 2, result.stderr
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1 and message in lines[0], result.stderr
        assert "Traceback" not in result.stderr
        assert not out.exists()


def test_a_survey_file_that_is_not_one_person_is_refused(points, tmp_path):
    two = tmp_path / "two.csv"
    two.write_text("stature,weightkg\n1700,700\n1800,800\n")
    result = run_cli("evaluate", "--points", str(points), "--measurements", str(two))
    assert result.returncode == 2
    assert result.stderr.strip().endswith("2 rows; expected one person's")


def test_a_file_that_is_not_a_csv_is_one_line(points, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("stature,weightkg\n1700,700\n1800,800,9\n")
    result = run_cli("evaluate", "--points", str(points), "--measurements", str(bad))
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "--measurements" in lines[0] and "not a CSV file" in lines[0]
