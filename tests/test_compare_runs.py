"""experiments/analysis/compare_runs.py: two results folders (copies of committed tables,
perturbed) and two landscape caches (written by the cache's own writer) compared."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ergohandover.landscape.cache import Landscape, landscape_path
from ergohandover.landscape.grid import Grid
from ergohandover.twin.task import Boundary

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "results"
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))

import compare_runs  # noqa: E402

TABLES = ("landscape/stats.csv", "landscape/manifest.json", "learning/runs.csv",
          "learning/targets.csv", "baselines/baselines.csv", "baselines/paths/start1_optimised.csv")
KEY = "0123456789abcdef"


def copy_results(folder: Path) -> Path:
    for name in TABLES:
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(RESULTS / name, folder / name)
    return folder


@pytest.fixture
def pair(tmp_path):
    return copy_results(tmp_path / "a"), copy_results(tmp_path / "b")


def edit(folder: Path, name: str, change) -> None:
    """Rewrite a CSV with ``change(table)`` applied (cells read and written as text)."""
    table = pd.read_csv(folder / name, dtype=str, keep_default_na=False)
    change(table)
    table.to_csv(folder / name, index=False)


def run(capsys, *args) -> tuple[int, str]:
    code = compare_runs.main([str(a) for a in args])
    return code, capsys.readouterr().out


def lines_of(out: str, name: str) -> str:
    """The report's lines on ``name`` (its line and the indented ones under it)."""
    block, inside = [], False
    for line in out.splitlines():
        if not line.startswith("    "):
            inside = line.startswith(f"{name}:")
        if inside:
            block.append(line)
    return "\n".join(block)


def test_identical_folders_match(pair, capsys):
    code, out = run(capsys, *pair)
    assert code == 0, out
    assert "everything matches" in out
    assert "5 CSV files compared, 0 differ" in out


def test_a_changed_score_cell_names_the_file_and_column(pair, capsys):
    edit(pair[1], "landscape/stats.csv", lambda t: t.__setitem__("min", ["9", *t["min"][1:]]))
    code, out = run(capsys, *pair)
    assert code == 1
    report = lines_of(out, "landscape/stats.csv")
    assert "DIFFERS" in report and "column min: 1 rows differ" in report


def test_a_csv_missing_from_one_side_differs(pair, capsys):
    (pair[1] / "baselines" / "paths" / "start1_optimised.csv").unlink()
    code, out = run(capsys, *pair)
    assert code == 1
    assert "baselines/paths/start1_optimised.csv: DIFFERS: missing in B" in out


def test_wall_times_may_differ_and_their_spread_is_printed(pair, capsys):
    def slower(table):
        table["elapsed_s"] = [f"{2 * float(v)!r}" for v in table["elapsed_s"]]
    edit(pair[1], "learning/runs.csv", slower)
    code, out = run(capsys, *pair)
    assert code == 0, out
    report = lines_of(out, "learning/runs.csv")
    assert "elapsed_s (time, tolerated)" in report
    assert "median 2.00, range 2.00-2.00" in report


def test_wall_clock_capped_runs_are_left_out_but_step_budgeted_ones_must_repeat(pair, capsys):
    def as_wall_clock_run(table):
        # The default study has none (its wall-clock caps are configs/paper.json's): the first
        # run becomes one in both folders, as that configuration's runs.csv holds them.
        table.loc[0, "budget"], table.loc[0, "steps"] = "wall-120s", ""

    for folder in pair:
        edit(folder, "learning/runs.csv", as_wall_clock_run)

    def capped(row_filter):
        def change(table):
            row = table.index[row_filter(table)][0]
            table.loc[row, "best_score"] = "99.0"
        return change
    edit(pair[1], "learning/runs.csv", capped(lambda t: t["budget"].str.startswith("wall-")))
    code, out = run(capsys, *pair)
    assert code == 0, out
    assert "1 of them differ" in lines_of(out, "learning/runs.csv")
    edit(pair[1], "learning/runs.csv", capped(lambda t: t["steps"] != ""))
    code, out = run(capsys, *pair)
    assert code == 1
    assert "column best_score" in lines_of(out, "learning/runs.csv")


@pytest.mark.parametrize(("added", "code"), [(9, 0), (10, 1)])
def test_the_planners_pose_checks_may_vary_by_nine(pair, capsys, added, code):
    edit(pair[1], "baselines/baselines.csv", lambda t: t.__setitem__(
        "checks", [str(int(v) + added) for v in t["checks"]]))
    got, out = run(capsys, *pair)
    assert got == code, out
    assert f"max abs diff {added}" in lines_of(out, "baselines/baselines.csv")


def test_path_lengths_may_differ_in_their_last_digits_only(pair, capsys):
    def nudge(factor):
        return lambda t: t.__setitem__("path_length_m", [repr(float(v) * factor)
                                                         for v in t["path_length_m"]])
    edit(pair[1], "baselines/baselines.csv", nudge(1 + 1e-15))
    assert run(capsys, *pair)[0] == 0
    edit(pair[1], "baselines/baselines.csv", nudge(1 + 1e-9))
    assert run(capsys, *pair)[0] == 1


PARTICIPANTS = "participants/participants.csv"


def with_participants(pair, value: str) -> tuple[int, str]:
    """Both folders with the committed participants table, B's first robot clearance ``value``
    (a rerun's clearance differed in its 16th digit: 0.056089047391000214 vs
    0.05608904739100045); the comparison's exit code and its lines on the table."""
    for folder in pair:
        (folder / PARTICIPANTS).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(RESULTS / PARTICIPANTS, folder / PARTICIPANTS)
    edit(pair[1], PARTICIPANTS, lambda t: t.loc.__setitem__((0, "robot_clearance_m"), value))
    return compare_runs.compare(*pair, [], None), PARTICIPANTS


def test_a_float_differing_in_its_16th_digit_matches_and_says_so(pair, capsys):
    assert pd.read_csv(RESULTS / PARTICIPANTS, dtype=str)["robot_clearance_m"][0] == (
        "0.05608904739100045")  # the committed value the rerun's differed from
    ok, name = with_participants(pair, "0.056089047391000214")
    out = capsys.readouterr().out
    assert ok, out
    report = lines_of(out, name)
    assert report.startswith(f"{name}: within tolerance")
    assert ("robot_clearance_m (floating point, tolerated): 1 rows differ in their last digits, "
            "max rel diff 4.2e-15 (tolerance 1e-09)") in report
    assert "everything matches" in out


@pytest.mark.parametrize("relative", [1e-6, -1e-6, 2e-9])
def test_a_float_differing_beyond_the_relative_tolerance_differs(pair, capsys, relative):
    value = 0.05608904739100045 * (1 + relative)
    ok, name = with_participants(pair, repr(value))
    out = capsys.readouterr().out
    assert not ok
    report = lines_of(out, name)
    assert (f"column robot_clearance_m: 1 rows differ, first at line 2: '0.05608904739100045' "
            f"vs '{value!r}' (rel diff {abs(relative):.2g}, tolerance 1e-09)") in report
    assert "DIFFERENCES found" in out


@pytest.mark.parametrize(("a", "b"), [
    ("2256448245", "2256448246"),  # an integer: relative 4e-10, still a difference
    ("1", "1.0"),  # an integer against a float: the column's type changed
    ("0.5", ""),  # a float against an empty cell
    ("0.5", "nan"),
    ("inf", "1e308"),
])
def test_integers_text_and_empty_cells_compare_exactly(pair, capsys, a, b):
    def set_seed(value):
        return lambda t: t.loc.__setitem__((0, "seed"), value)
    edit(pair[0], "learning/runs.csv", set_seed(a))
    edit(pair[1], "learning/runs.csv", set_seed(b))
    code, out = run(capsys, *pair)
    assert code == 1, out
    assert (f"column seed: 1 rows differ, first at line 2: {a!r} vs {b!r}"
            in lines_of(out, "learning/runs.csv"))


def test_a_column_of_its_own_keeps_its_rule_over_the_float_one(pair, capsys):
    # path_length_m's measured rule (1e-12) is tighter than the floats' (1e-9)
    edit(pair[1], "baselines/baselines.csv", lambda t: t.__setitem__(
        "path_length_m", [repr(float(v) * (1 + 1e-10)) for v in t["path_length_m"]]))
    code, out = run(capsys, *pair)
    assert code == 1
    assert "column path_length_m beyond its tolerance" in lines_of(out, "baselines/baselines.csv")


def test_help_names_the_landscape_options(capsys):
    with pytest.raises(SystemExit) as exit_:
        compare_runs.main(["--help"])
    out = capsys.readouterr().out
    assert exit_.value.code == 0
    assert "--cache-a DIR" in out and "--cache-b DIR" in out and "RESULTS_A" in out
    assert "floating-point cells (rel 1e-09" in " ".join(out.split())


@pytest.mark.parametrize(("args", "named"), [
    (["A", "MISSING"], "RESULTS_B = "), (["A", "B", "--cache-a", "MISSING", "--cache-b", "B"],
                                          "--cache-a = "),
    (["A", "B", "--cache-a", "B"], "--cache-a and --cache-b"), (["A"], "RESULTS_B"),
    (["A", "B", "nopart"], "PART = 'nopart'")])
def test_bad_usage_exits_2_with_one_line_naming_the_argument(pair, tmp_path, capsys, args,
                                                             named):
    folders = {"A": str(pair[0]), "B": str(pair[1]), "MISSING": str(tmp_path / "missing")}
    with pytest.raises(SystemExit) as exit_:
        compare_runs.main([folders.get(a, a) for a in args])
    err = capsys.readouterr().err
    assert exit_.value.code == 2
    assert len(err.strip().splitlines()) == 1 and named in err


def write_landscape(cache: Path, monkeypatch, key: str = KEY, changed: bool = False) -> None:
    """A 27-point landscape written by the cache's own writer into ``cache``."""
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(cache))
    grid = Grid(Boundary((0.0, 0.02), (1.0, 1.02), (0.4, 0.42)), 0.01)
    scores = np.arange(grid.size, dtype=np.int8) % 7
    if changed:
        scores[13] = 5
    arrays = {"flags": np.zeros(grid.size, np.uint8), "paper_postural": scores,
              "neck_flexion": np.linspace(0, 30, grid.size, dtype=np.float32)}
    Landscape(grid, key, arrays, {"seconds": 1.0}).save(landscape_path(key))


def record_key(folder: Path, key: str = KEY) -> None:
    path = folder / "landscape" / "manifest.json"
    path.write_text(json.dumps({**json.loads(path.read_text()), "landscape_key": key}))
    edit(folder, "learning/targets.csv", lambda t: t.__setitem__("landscape_key", key))


def test_landscapes_in_two_caches_are_compared_bit_for_bit(pair, tmp_path, capsys,
                                                           monkeypatch):
    caches = tmp_path / "cache_a", tmp_path / "cache_b"
    for folder in pair:
        record_key(folder)
    write_landscape(caches[0], monkeypatch)
    write_landscape(caches[1], monkeypatch)
    options = ["--cache-a", caches[0], "--cache-b", caches[1]]
    code, out = run(capsys, *pair, *options)
    assert code == 0, out
    assert f"landscape {KEY}: identical, 3 arrays of 27 points" in out
    write_landscape(caches[1], monkeypatch, changed=True)
    code, out = run(capsys, *pair, *options)
    assert code == 1
    assert (f"landscape {KEY}: DIFFERS: paper_postural at 1 of 27 points, first point 13 at "
            "(0.010, 1.010, 0.410) m: 6 vs 5") in out
    code, out = run(capsys, *pair)  # one cache: the same key is the same file
    assert code == 0
    assert f"landscape {KEY}: same key in the same cache: identical by construction" in out


def test_a_recorded_landscape_missing_from_a_cache_differs(pair, tmp_path, capsys, monkeypatch):
    caches = tmp_path / "cache_a", tmp_path / "cache_b"
    for folder in pair:
        record_key(folder)
    write_landscape(caches[0], monkeypatch)
    caches[1].mkdir()
    code, out = run(capsys, *pair, "--cache-a", caches[0], "--cache-b", caches[1])
    assert code == 1
    assert f"landscape {KEY}: DIFFERS: not in the cache" in out


def test_every_committed_csv_is_compared(capsys):
    code, out = run(capsys, RESULTS, RESULTS)
    assert code == 0, out
    compared = {line.split(":")[0] for line in out.splitlines()
                if line.split(":")[0].endswith(".csv")}
    on_disk = {p.relative_to(RESULTS).as_posix() for p in RESULTS.rglob("*.csv")
               if p.relative_to(RESULTS).parts[0] != "quick"}
    assert compared == on_disk
    assert f"{len(on_disk)} CSV files compared, 0 differ" in out
