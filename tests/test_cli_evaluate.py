"""``ergohandover evaluate`` end to end: CSV out, renders, and one-line errors for bad points."""

from __future__ import annotations

import io
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
from cli_run import run_cli
from PIL import Image

from ergohandover.cli import main
from ergohandover.twin.evaluate import EVALUATION_COLUMNS
from ergohandover.workload import SHIFT_COLUMNS, WORKLOAD_COLUMNS


def test_evaluates_points_and_renders_one_png_each(tmp_path):
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0,1.10,0.35\n0.1,1.3,0.45\n")
    out, renders = tmp_path / "eval.csv", tmp_path / "renders"
    assert main(["evaluate", "--points", str(points), "--output", str(out), "--render",
                 str(renders), "--workers", "1"]) == 0
    table = pd.read_csv(out, keep_default_na=False)
    assert list(table.columns) == [*EVALUATION_COLUMNS, *WORKLOAD_COLUMNS, *SHIFT_COLUMNS]
    assert table["feasible"].tolist() == [1, 1]
    pngs = sorted(renders.glob("*.png"))
    assert [p.name for p in pngs] == ["point_0001.png", "point_0002.png"]
    image = Image.open(pngs[0])
    assert image.width == 960 and image.height > 480
    # Not a blank frame: the worker and the box put many colours in it.
    assert len(image.convert("RGB").getcolors(maxcolors=1 << 20)) > 50


def evaluate_stdout(*flags: str) -> pd.DataFrame:
    result = subprocess.run(
        [sys.executable, "-m", "ergohandover.cli", "evaluate", "--points", "-", "--output", "-",
         *flags], input="x,y,z\n0,1.0,0.35\n0,1.3,0.40\n", capture_output=True, text=True,
        timeout=300)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].startswith("x,y,z,feasible") and len(lines) == 3  # nothing but the CSV
    return pd.read_csv(io.StringIO(result.stdout))


@pytest.mark.slow
def test_stdout_is_pure_csv_and_body_flags_change_the_posture():
    default = evaluate_stdout()
    small = evaluate_stdout("--percentile", "p5-female")
    tall = evaluate_stdout("--stature", "1.95", "--mass", "95", "--sex", "male")
    # The same box locations are reached differently by workers of other sizes: a shorter
    # worker bends less to a low box and raises the arms more to a high one.
    for column in ("trunk_flexion", "left_upper_arm_flexion", "left_elbow_flexion"):
        assert not np.allclose(default[column], small[column], atol=0.5), column
        assert not np.allclose(default[column], tall[column], atol=0.5), column
    assert small["trunk_flexion"].iloc[0] < default["trunk_flexion"].iloc[0] \
        < tall["trunk_flexion"].iloc[0]


@pytest.mark.slow
def test_the_gaze_flag_changes_the_neck_only_where_the_box_is_out_of_view():
    on, off = evaluate_stdout(), evaluate_stdout("--gaze", "off")
    assert not np.allclose(on["neck_flexion"], off["neck_flexion"], atol=0.5)
    assert (off["neck_flexion"].abs() <= on["neck_flexion"].abs() + 0.5).all()


@pytest.mark.slow
def test_the_pybullet_solver_flag_changes_the_solver():
    ours, theirs = evaluate_stdout(), evaluate_stdout("--solver", "pybullet")
    assert not np.allclose(ours["neck_flexion"], theirs["neck_flexion"], atol=0.5)


@pytest.mark.parametrize(("content", "args", "message"), [
    ("x,y\n0,1\n", (), "missing required column 'z'"),
    ("x,y,z\n0,1,abc\n", (), "row 1, column 'z': 'abc' is not a number"),
    ("x,y,z\n0,1,0.4\n0,nan,0.4\n", (), "row 2, column 'y': nan is not allowed"),
    ("", (), "is empty"),
    ("x,y,z\n0,1,0.4\n", ("--stature", "2.5"), "--stature 2.5: outside 1.4-2.1 m"),
    ("x,y,z\n0,1,0.4\n", ("--workers", "0"), "--workers 0: must be >= 1"),
    ("x,y,z\n0,1,0.4\n", ("--box-mass-kg", "40"), "--box-mass-kg 40: outside 0-25 kg"),
])
def test_bad_points_or_flags_exit_2_with_one_line(tmp_path, content, args, message):
    points = tmp_path / "points.csv"
    points.write_text(content)
    out = tmp_path / "eval.csv"
    result = run_cli("evaluate", "--points", str(points), "--output", str(out), *args)
    assert result.returncode == 2
    assert message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and "Traceback" not in result.stderr
    assert not out.exists()
