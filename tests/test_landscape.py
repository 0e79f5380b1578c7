"""The grid, the exhaustive sweep (cache, resume after kill -9, corruption) and its statistics."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from ergohandover.cli import main
from ergohandover.landscape import sweep as landscape_module
from ergohandover.landscape.grid import Grid, parse_boundary
from ergohandover.landscape.stats import most_symmetric, statistics
from ergohandover.landscape.sweep import Landscape, LandscapeError, sweep
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import REASONS, Evaluator, evaluate
from ergohandover.twin.task import Boundary, TaskSpec, TaskSpecError

SMALL = Boundary((-0.10, 0.10), (1.00, 1.20), (0.35, 0.50))


def test_the_paper_code_grid_has_the_papers_size():
    grid = Grid(Boundary.paper_code(), 0.003)
    assert grid.shape == (134, 241, 101)
    assert 3.2e6 < grid.size < 3.3e6
    x, y, z = grid.axes()
    assert x[0] == -0.20 and y[0] == 0.72 and z[0] == 0.30
    assert abs(x[-1] - 0.199) < 1e-12 and abs(y[-1] - 1.44) < 1e-12
    np.testing.assert_array_equal(grid.points(0, 3)[:, 2], 0.30 + np.arange(3) * 0.003)
    last = grid.coordinates(np.array([grid.size - 1]))[0]
    np.testing.assert_allclose(last, [x[-1], y[-1], z[-1]])


@pytest.mark.parametrize(("boundary", "step", "message"), [
    (SMALL, 0.0, "step = 0.0 is outside the valid range"),
    (SMALL, -0.01, "step = -0.01"),
    (SMALL, 0.3, "step = 0.3 m is larger than the boundary along x"),
])
def test_bad_steps_are_rejected(boundary, step, message):
    with pytest.raises(TaskSpecError, match=message):
        Grid(boundary, step)


@pytest.mark.parametrize(("text", "message"), [
    ("0.1,-0.1,1,1.2,0.3,0.5", "boundary x = 0.1..-0.1 is empty or inverted"),
    ("0,0,1,1.2,0.3,0.5", "boundary x = 0..0 is empty"),
    ("1,2,3", "boundary = '1,2,3' is not allowed"),
    ("round", "boundary = 'round' is not allowed"),
])
def test_bad_boundaries_are_rejected(text, message):
    with pytest.raises(TaskSpecError, match=message):
        parse_boundary(text, BodySpec(), TaskSpec())


def test_the_body_boundary_follows_the_worker():
    small, big = BodySpec.from_percentile("p5-female"), BodySpec.from_percentile("p95-male")
    a, b = (parse_boundary("body", w, TaskSpec()) for w in (small, big))
    assert a.y[1] == small.stature_m and b.y[1] == big.stature_m
    assert a.x[1] < b.x[1] and a.z[1] < b.z[1]


def test_the_landscape_holds_what_evaluate_says(tmp_path):
    grid = Grid(SMALL, 0.05)
    landscape, reused = sweep(grid, Evaluator(), tmp_path / "l.npz", progress=False)
    assert not reused and landscape.grid == grid
    rows = evaluate(grid.points())
    feasible = rows["feasible"].to_numpy() == 1
    np.testing.assert_array_equal(landscape.feasible, feasible)
    for name in ("paper_postural", "reba", "rula"):
        np.testing.assert_array_equal(landscape.arrays[name][feasible],
                                      rows[name][feasible].to_numpy())
    np.testing.assert_allclose(landscape.arrays["trunk_flexion"], rows["trunk_flexion"],
                               atol=1e-4)
    for bit, reason in enumerate(REASONS):
        has = rows["reason"].str.split(";").apply(lambda r, reason=reason: reason in r)
        np.testing.assert_array_equal((landscape.arrays["flags"] >> bit) & 1, has)


def test_a_matching_file_is_reused_and_a_mismatched_one_recomputed(tmp_path):
    out = tmp_path / "l.npz"
    grid = Grid(SMALL, 0.05)
    first, _ = sweep(grid, Evaluator(), out, progress=False)
    again, reused = sweep(grid, Evaluator(), out, progress=False)
    assert reused and again.key == first.key
    other, reused = sweep(grid, Evaluator(body=BodySpec.from_percentile("p95-male")), out,
                          progress=False)
    assert not reused and other.key != first.key
    assert Landscape.load(out).key == other.key


def test_a_corrupted_file_is_detected_and_recomputed(tmp_path):
    out = tmp_path / "l.npz"
    grid = Grid(SMALL, 0.05)
    good, _ = sweep(grid, Evaluator(), out, progress=False)
    # A file cut short (a copy interrupted, a full disk) cannot be read.
    out.write_bytes(out.read_bytes()[: out.stat().st_size // 2])
    with pytest.raises(LandscapeError, match="not a readable landscape"):
        Landscape.load(out, good.key)
    again, reused = sweep(grid, Evaluator(), out, progress=False)
    assert not reused
    np.testing.assert_array_equal(again.arrays["reba"], good.arrays["reba"])
    # A well-formed file whose numbers were changed fails its checksum.
    with np.load(out) as data:
        arrays = {name: data[name] for name in data.files}
    arrays["reba"] = arrays["reba"].copy()
    arrays["reba"][0] += 1
    np.savez_compressed(out, **arrays)
    with pytest.raises(LandscapeError, match="checksum"):
        Landscape.load(out, good.key)
    assert not sweep(grid, Evaluator(), out, progress=False)[1]


def test_an_interrupted_sweep_resumes_without_redoing_parts(tmp_path, monkeypatch):
    monkeypatch.setattr(landscape_module, "PART", 20)
    grid = Grid(SMALL, 0.05)
    out = tmp_path / "l.npz"
    partial, _ = sweep(grid, Evaluator(), out, progress=False, stop_after_parts=2)
    assert partial is None and not out.exists()
    assert len(list((tmp_path / "l.npz.parts").glob("part_*.npz"))) == 2
    resumed, _ = sweep(grid, Evaluator(), out, progress=False)
    assert resumed.meta["points_computed"] == grid.size - 40
    fresh, _ = sweep(grid, Evaluator(), tmp_path / "fresh.npz", progress=False)
    for name in fresh.arrays:
        np.testing.assert_array_equal(resumed.arrays[name], fresh.arrays[name], err_msg=name)
    assert not (tmp_path / "l.npz.parts").exists()


def test_kill_9_mid_sweep_then_rerun_gives_the_same_file(tmp_path, monkeypatch):
    monkeypatch.setattr(landscape_module, "PART", 500)
    out = tmp_path / "l.npz"
    script = textwrap.dedent(f"""
        from pathlib import Path
        from ergohandover.landscape import sweep as landscape
        from ergohandover.twin.evaluate import Evaluator
        from ergohandover.landscape.grid import Grid
        from ergohandover.twin.task import Boundary
        landscape.PART = 500
        grid = Grid(Boundary((-0.10, 0.10), (1.0, 1.2), (0.35, 0.5)), 0.01)
        landscape.sweep(grid, Evaluator(), Path({str(out)!r}), workers=2, progress=False)
    """)
    proc = subprocess.Popen([sys.executable, "-c", script])
    parts = tmp_path / "l.npz.parts"
    deadline = time.time() + 120
    while len(list(parts.glob("part_*.npz"))) < 2 and time.time() < deadline:
        time.sleep(0.05)
    proc.kill()  # SIGKILL: no clean-up runs
    proc.wait()
    assert not out.exists() and len(list(parts.glob("part_*.npz"))) >= 2
    grid = Grid(SMALL, 0.01)
    resumed, _ = sweep(grid, Evaluator(), out, progress=False)
    assert resumed.meta["points_computed"] < grid.size
    fresh, _ = sweep(grid, Evaluator(), tmp_path / "fresh.npz", progress=False)
    for name in fresh.arrays:
        np.testing.assert_array_equal(resumed.arrays[name], fresh.arrays[name], err_msg=name)


def test_a_boundary_with_no_feasible_point_is_an_error(tmp_path):
    inside_the_chest = Boundary((-0.05, 0.05), (1.2, 1.3), (0.0, 0.08))
    with pytest.raises(LandscapeError, match="no feasible point"):
        sweep(Grid(inside_the_chest, 0.04), Evaluator(), tmp_path / "l.npz", progress=False)
    assert not (tmp_path / "l.npz").exists()


def test_statistics_find_the_minimum_and_the_most_symmetric_minimiser(tmp_path):
    landscape, _ = sweep(Grid(SMALL, 0.05), Evaluator(), tmp_path / "l.npz", progress=False)
    stats = statistics(landscape).set_index("score")
    for score in ("paper_postural", "reba", "rula"):
        values = landscape.arrays[score][landscape.feasible]
        row = stats.loc[score]
        assert row["min"] == values.min() and row["n_at_min"] == (values == values.min()).sum()
        assert row["x_min"] <= row["best_x"] <= row["x_max"]
    points = np.array([[0.1, 1, 0.4], [0.0, 1.2, 0.5], [0.0, 1.1, 0.45], [0.0, 1.0, 0.4]])
    assert most_symmetric(points) == 2


def test_sweep_and_stats_commands(tmp_path, capsys):
    out = tmp_path / "l.npz"
    args = ["sweep", "--boundary=-0.1,0.1,1.0,1.2,0.35,0.5", "--step", "0.05", "--output",
            str(out), "--workers", "1"]
    assert main(args) == 0
    for suffix in ("_stats.csv", "_distribution.csv", "_distribution.png"):
        assert (tmp_path / f"l{suffix}").exists()
    assert (tmp_path / "manifest.json").exists()
    assert main(["landscape-stats", str(out)]) == 0
    assert "paper_postural" in capsys.readouterr().out
    assert main(args) == 0
    assert "reusing" in capsys.readouterr().err


@pytest.mark.parametrize(("args", "message"), [
    (["--boundary", "0.1,-0.1,1,1.2,0.3,0.5"], "empty or inverted"),
    (["--step", "0"], "step = 0.0 is outside"),
    (["--boundary", "elsewhere"], "boundary = 'elsewhere' is not allowed"),
])
def test_bad_sweep_arguments_exit_2(tmp_path, args, message):
    result = subprocess.run([sys.executable, "-m", "ergohandover.cli", "sweep", "--output",
                             str(tmp_path / "l.npz"), *args], capture_output=True, text=True)
    assert result.returncode == 2 and message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_stats_of_a_corrupted_file_exit_2(tmp_path):
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"not a landscape")
    result = subprocess.run([sys.executable, "-m", "ergohandover.cli", "landscape-stats",
                             str(bad)], capture_output=True, text=True)
    assert result.returncode == 2 and "not a readable landscape" in result.stderr
