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


@pytest.mark.slow
def test_an_elbow_height_sizes_the_worker_that_evaluate_solves(points, tmp_path):
    out = tmp_path / "low_elbow.csv"
    assert main(["evaluate", "--points", str(points), "--output", str(out),
                 "--elbow-height", "1.02"]) == 0
    # No percentile named: stature, mass and the rest are the body model's given the elbow.
    body = BodySpec.from_measurements({"elbow_height_m": 1.02})
    assert body.stature_m < BodySpec().stature_m
    expected = evaluate(pd.read_csv(points).to_numpy(float), Evaluator(body))
    table = pd.read_csv(out, keep_default_na=False)
    assert table["paper_postural"].tolist() == expected["paper_postural"].tolist()
    assert table["right_elbow_flexion"].to_numpy() == pytest.approx(
        expected["right_elbow_flexion"].to_numpy(), abs=1e-6)


@pytest.mark.slow
def test_a_body_given_by_stature_and_sex_is_the_body_models_and_is_said(points, tmp_path):
    """A 1.62 m woman weighs what the survey's 1.62 m women weigh, not the default 50th man's
    84.3 kg; a named percentile keeps its own size but for what is given; each run says the
    body it used, last, once it has finished."""
    from cli_run import run_cli

    woman = BodySpec.from_measurements({"stature_m": 1.62}, "female")
    assert 60 < woman.mass_kg < 75 and woman.elbow_height_m < BodySpec().elbow_height_m
    out = tmp_path / "woman.csv"
    done = run_cli("evaluate", "--points", str(points), "--output", str(out),
                   "--stature", "1.62", "--sex", "female")
    assert done.returncode == 0, done.stderr
    last = done.stderr.strip().splitlines()[-1]
    assert last == (f"worker: female, 1.620 m, {woman.mass_kg:.1f} kg, elbow height "
                    f"{woman.elbow_height_m:.3f} m (the body model's, given --sex, --stature)")
    expected = evaluate(pd.read_csv(points).to_numpy(float), Evaluator(woman))
    assert pd.read_csv(out)["trunk_flexion"].to_numpy() == pytest.approx(
        expected["trunk_flexion"].to_numpy(), abs=1e-6)
    done = run_cli("evaluate", "--points", str(points), "--output", str(out),
                   "--percentile", "p5-female", "--mass", "60")
    small = BodySpec.from_percentile("p5-female")
    assert done.stderr.strip().splitlines()[-1].startswith(
        f"worker: female, {small.stature_m:.3f} m, 60.0 kg")


@pytest.mark.slow
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
