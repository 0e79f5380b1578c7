"""Bad input is refused before any work: one line naming the flag or column as typed, exit 2,
nothing written — outputs that cannot be written, files that would be misread, and work too
large to start without being asked."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from cli_run import run_cli

from ergohandover.io.atomic import OutputError, atomic_write_all
from ergohandover.io.csv_input import InputError, check_header

ROOT = Path(__file__).resolve().parents[1]
POSTURES = ROOT / "examples" / "postures.csv"
UNWRITABLE = Path("/proc/ergohandover-out")  # a virtual file system: nothing can be made there
needs_proc = pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs Linux's /proc")


def refused(*argv: str, stdin: str = "") -> str:
    done = run_cli(*argv, stdin=stdin)
    assert done.returncode == 2, (done.returncode, done.stderr)
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in done.stderr, done.stderr
    return lines[0]


@needs_proc
def test_an_unwritable_output_is_refused_before_the_first_handover_is_asked():
    done = run_cli("personalise", "--oracle", "ask", "--output", str(UNWRITABLE),
                   "--stature", "1.62", "--sex", "female", stdin="6\n" * 5)
    assert done.returncode == 2
    assert done.stdout == ""  # no trial was proposed, no answer read
    assert done.stderr.strip() == (f"ergohandover personalise: error: --output {UNWRITABLE}: "
                                   "cannot be written (No such file or directory in '/proc')")


@needs_proc
def test_a_second_unwritable_output_keeps_the_first_from_being_written(tmp_path):
    out = tmp_path / "r.csv"
    line = refused("robustness", "--postures", str(POSTURES), "--output", str(out), "--flips",
                   str(UNWRITABLE / "f.csv"))
    assert f"--flips {UNWRITABLE / 'f.csv'}: cannot be written" in line
    assert ".tmp" not in line and not out.exists()


@needs_proc
def test_the_studys_results_folder_is_checked_first():
    done = subprocess.run([sys.executable, str(ROOT / "experiments" / "run_all.py"), "--only",
                           "figures", "--results", str(UNWRITABLE)], capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 2
    assert done.stderr.strip() == (f"run_all: error: --results {UNWRITABLE}: cannot be "
                                   "written (No such file or directory in '/proc')")


def test_several_files_are_written_all_or_none(tmp_path):
    first, second = tmp_path / "a.csv", tmp_path / "missing" / "b.csv"
    with pytest.raises(OutputError, match=f"^{second}: cannot be written"):
        atomic_write_all({first: lambda h: h.write("a\n"), second: lambda h: h.write("b\n")})
    assert list(tmp_path.iterdir()) == []  # neither file, no temporary left
    atomic_write_all({first: lambda h: h.write("a\n"), tmp_path / "c.csv": lambda h: h.write(
        "c\n")})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "c.csv"]


def test_a_column_given_twice_is_refused(tmp_path):
    table = pd.read_csv(POSTURES)
    text = POSTURES.read_text().splitlines()
    text[0] = text[0] + ",trunk_flexion"
    text[1:] = [row + ",99" for row in text[1:]]
    twice = tmp_path / "twice.csv"
    twice.write_text("\n".join(text) + "\n")
    assert len(table.columns) + 1 == len(text[0].split(","))
    line = refused("score", "--input", str(twice), "--output", str(tmp_path / "s.csv"))
    assert line.endswith(f"{twice}: column 'trunk_flexion' is given twice (give each column "
                         "once)")
    assert not (tmp_path / "s.csv").exists()


@pytest.mark.parametrize("mark, word", [(";", "semicolons"), ("\t", "tabs")])
def test_a_file_not_separated_by_commas_says_so(tmp_path, mark, word):
    text = POSTURES.read_text().replace(",", mark)
    path = tmp_path / "semi.csv"
    path.write_text(text)
    line = refused("score", "--input", str(path), "--output", str(tmp_path / "s.csv"))
    assert line.endswith(f"{path}: its columns are separated by {word}, not commas (save it "
                         "as comma-separated CSV)")
    with pytest.raises(InputError, match="twice"):
        check_header("x,y,x", "f")
    check_header("x", "f")  # one column, no other separator: fine


@pytest.mark.parametrize("row, message", [
    ("statur,weightkg\n1720,850\n", "column 'statur' is not an ANSUR II survey column; the "
                                    "closest is 'stature'"),
    ("stature,weightkg\n1.72,850\n", "stature = 1.72 looks like metres; the survey's columns "
                                     "are millimetres"),
    ("stature,acromialheight\n1720,143.5\n", "acromialheight = 143.5 looks like centimetres"),
    ("stature,weightkg\n1720,85\n", "weightkg = 85 looks like whole kilograms; the survey's "
                                    "columns are tenths of a kilogram"),
])
def test_measurements_with_a_misspelt_column_or_another_unit_are_refused(tmp_path, row,
                                                                         message):
    person = tmp_path / "person.csv"
    person.write_text(row)
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0,1.0,0.4\n")
    line = refused("evaluate", "--points", str(points), "--measurements", str(person),
                   "--output", str(tmp_path / "e.csv"))
    assert f"--measurements {person}: {message}" in line
    assert not (tmp_path / "e.csv").exists()


def test_an_angle_sd_beyond_the_physical_bound_is_refused():
    line = refused("robustness", "--postures", str(POSTURES), "--angle-sd", "500")
    assert line.endswith("--angle-sd 500: outside 0-45 deg")


def test_too_many_draws_need_yes_and_an_estimate_is_given_first(tmp_path):
    out = tmp_path / "r.csv"
    line = refused("robustness", "--postures", str(POSTURES), "--draws", "100000000",
                   "--output", str(out))
    assert "--draws 100000000: 300,000,000 measured postures, too much memory at once" in line
    assert " GB of memory on this machine); give --yes to run it" in line and "min" in line
    assert not out.exists()


def test_a_grid_too_fine_needs_yes_and_an_estimate_is_given_first(tmp_path):
    line = refused("sweep", "--step", "0.0001", "--output", str(tmp_path / "sweep"))
    assert "--step 0.0001: 86,462,414,201 points, more than 20,000,000 (about " in line
    assert line.endswith("GB of memory on this machine); give --yes to run it")
    assert not (tmp_path / "sweep").exists()
