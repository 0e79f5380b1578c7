"""``ergohandover score`` end to end, including every kind of bad input."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from cli_run import run_cli

from ergohandover.cli import main
from ergohandover.ergonomics import MAIN_SCORE_COLUMNS, SCORE_COLUMNS
from ergohandover.workload.back import COLUMNS as BACK_COLUMNS
from ergohandover.workload.owas import COLUMNS as OWAS_COLUMNS
from ergohandover.workload.strength import SHIFT_COLUMNS

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "postures.csv"




def test_scores_the_example_and_keeps_every_input_column(tmp_path):
    out = tmp_path / "scores.csv"
    assert main(["score", "--input", str(EXAMPLE), "--output", str(out)]) == 0
    table = pd.read_csv(out)
    source = pd.read_csv(EXAMPLE)
    # Then OWAS, the back load (no lifting columns: the file gives no box location) and the
    # shift.
    assert list(table.columns) == [*source.columns, *SCORE_COLUMNS, *OWAS_COLUMNS,
                                   *BACK_COLUMNS, *SHIFT_COLUMNS]
    pd.testing.assert_frame_equal(table[source.columns], source)
    assert table["reba"].tolist() == [1, 9, 9]
    assert table["rula"].tolist() == [3, 7, 7]
    assert table["paper_postural"].tolist() == [6, 10, 7]
    assert set(MAIN_SCORE_COLUMNS) <= set(table.columns)
    assert not list(tmp_path.glob(".*.tmp")), "temporary file left behind"


@pytest.mark.slow
def test_stdin_to_stdout_through_the_console_entry():
    # The one spawned process of the file: the module entry as a user's shell runs it.
    result = subprocess.run([sys.executable, "-m", "ergohandover.cli", "score", "--input", "-",
                             "--output", "-"], input=EXAMPLE.read_text(), capture_output=True,
                            text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.strip().splitlines()
    assert len(lines) == 4 and lines[0].endswith(SHIFT_COLUMNS[-1])


def test_settings_flags_change_the_scores(tmp_path):
    out = tmp_path / "s.csv"
    # Row 1 has the wrists at exactly 5°, the neutral tolerance: 'upper' makes RULA's wrist 2.
    main(["score", "--input", str(EXAMPLE), "--output", str(out), "--band-edge", "upper"])
    upper = pd.read_csv(out)
    main(["score", "--input", str(EXAMPLE), "--output", str(out)])
    lower = pd.read_csv(out)
    assert lower["rula_left_wrist"][0] == 1 and upper["rula_left_wrist"][0] == 2


def test_optional_columns_may_be_absent(tmp_path):
    frame = pd.read_csv(EXAMPLE).drop(columns=["name", "load_kg", "coupling"])
    src, out = tmp_path / "p.csv", tmp_path / "s.csv"
    frame.to_csv(src, index=False)
    assert main(["score", "--input", str(src), "--output", str(out)]) == 0
    table = pd.read_csv(out)
    assert "bilateral_support" not in table.columns  # defaults are not invented as columns
    assert (table["reba_load"] == 0).all()


def bad_csv(tmp_path: Path, mutate) -> Path:
    frame = pd.read_csv(EXAMPLE, dtype=str)
    mutate(frame)
    path = tmp_path / "bad.csv"
    frame.to_csv(path, index=False)
    return path


def set_cell(column: str, row: int, value: str):
    def mutate(frame):
        frame.loc[row, column] = value
    return mutate


BAD_INPUTS = {
    "nan": (set_cell("trunk_flexion", 1, "nan"), "row 2, column 'trunk_flexion': nan"),
    "inf": (set_cell("left_wrist_flexion", 2, "inf"),
            "row 3, column 'left_wrist_flexion': inf is not allowed"),
    "text": (set_cell("neck_flexion", 0, "forty"),
             "row 1, column 'neck_flexion': 'forty' is not a number"),
    "empty cell": (set_cell("neck_twist", 1, ""), "row 2, column 'neck_twist': an empty cell"),
    "coupling 5": (set_cell("coupling", 2, "5"),
                   "row 3, column 'coupling': 5 is not allowed (expected an integer 0-3)"),
    "negative load": (set_cell("load_kg", 0, "-2"),
                      "row 1, column 'load_kg': -2 is not allowed"),
    "missing column": (lambda f: f.pop("right_elbow_flexion"),
                       "missing required column 'right_elbow_flexion'"),
}


@pytest.mark.parametrize("case", list(BAD_INPUTS))
def test_bad_input_exits_2_with_one_line_and_loses_nothing(tmp_path, case):
    mutate, message = BAD_INPUTS[case]
    src = bad_csv(tmp_path, mutate)
    out = tmp_path / "scores.csv"
    out.write_text("previous results\n")
    result = run_cli("score", "--input", str(src), "--output", str(out))
    assert result.returncode == 2
    assert message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "Traceback" not in result.stderr
    assert out.read_text() == "previous results\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.csv", "scores.csv"]


@pytest.mark.parametrize(("content", "message"), [
    ("", "is empty"),
    (EXAMPLE.read_text().splitlines()[0] + "\n", "has a header but no rows"),
])
def test_empty_inputs_exit_2(tmp_path, content, message):
    src = tmp_path / "in.csv"
    src.write_text(content)
    result = run_cli("score", "--input", str(src), "--output", str(tmp_path / "out.csv"))
    assert result.returncode == 2 and message in result.stderr
    assert not (tmp_path / "out.csv").exists()


def test_keypoint_output_without_its_unseen_column_is_refused_with_the_way_out(tmp_path):
    # ZED BODY_34 cannot see the wrists: `score --keypoints` leaves those cells empty and names
    # them in its 'unseen' column (which `score --input` reads: tests/test_capture_formats.py);
    # without that column, an empty cell is refused naming where it comes from and the ways out.
    scored = tmp_path / "keypoints-scored.csv"
    keypoints = EXAMPLE.parent / "keypoints" / "zed34.npz"
    assert main(["score", "--keypoints", str(keypoints), "--format", "zed34", "--output",
                 str(scored)]) == 0
    pd.read_csv(scored, dtype=str, keep_default_na=False).drop(columns="unseen").to_csv(
        scored, index=False)
    again = run_cli("score", "--input", str(scored), "--output", str(tmp_path / "again.csv"))
    assert again.returncode == 2
    line = again.stderr.strip()
    assert "\n" not in line and ": an empty cell is not a number" in line
    assert line.endswith("an empty cell is a column the capture could not see (`score "
                         "--keypoints` leaves them empty and names them in its 'unseen' "
                         "column): keep that column, score the keypoints again with --assume "
                         "COLUMN=VALUE, or fill the cell")
    assert not (tmp_path / "again.csv").exists()


def test_a_missing_input_exits_2_and_a_missing_output_folder_is_created(tmp_path):
    result = run_cli("score", "--input", str(tmp_path / "nope.csv"), "--output", "-")
    assert result.returncode == 2 and "nope.csv does not exist" in result.stderr
    result = run_cli("score", "--input", str(EXAMPLE), "--output",
                     str(tmp_path / "no_dir" / "out.csv"))
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "no_dir" / "out.csv").is_file()


def test_a_bad_setting_exits_2_naming_the_field(tmp_path):
    result = run_cli("score", "--input", str(EXAMPLE), "--output", "-",
                     "--twist-from-deg", "45")
    assert result.returncode == 2
    assert "--twist-from-deg 45: outside 0-30 deg" in result.stderr


def test_many_rows_score_like_the_library(tmp_path):
    rng = np.random.default_rng(11)
    from ergohandover.ergonomics import Posture, score_postures

    p = Posture.random(500, rng)
    frame = pd.DataFrame({k: p[k] for k in p})
    src, out = tmp_path / "p.csv", tmp_path / "s.csv"
    frame.to_csv(src, index=False)
    assert main(["score", "--input", str(src), "--output", str(out)]) == 0
    table = pd.read_csv(out)
    expected = score_postures(p)
    for name in SCORE_COLUMNS:
        np.testing.assert_array_equal(table[name].to_numpy(), expected[name], err_msg=name)
