"""The grid, the landscape door (cache, resume after kill -9, corruption) and its statistics."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import ergohandover.landscape.cache as cache_module
import ergohandover.landscape.sweep as sweep_module
from ergohandover.cli import main
from ergohandover.ergonomics import ScoringSettings
from ergohandover.landscape import Landscape, LandscapeError, landscape_key, landscapes_of
from ergohandover.landscape.cache import landscape_path
from ergohandover.landscape.grid import Grid, parse_boundary
from ergohandover.landscape.stats import most_symmetric, statistics
from ergohandover.landscape.sweep import SweepInterrupted
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import REASONS, Evaluator, evaluate
from ergohandover.twin.solver import SolverSettings
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


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A landscape cache of this test's own."""
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def sweep(grid, evaluator=None, **kwargs):
    """(landscape, reused): one landscape through the door."""
    [done] = landscapes_of([evaluator or Evaluator()], grid, progress=False, **kwargs)
    return done.landscape, done.reused


def fresh_sweep(grid, tmp_path, monkeypatch, **kwargs):
    """The same grid swept from nothing, in a second, empty cache."""
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "fresh_cache"))
    return sweep(grid, **kwargs)[0]


def test_the_landscape_holds_what_evaluate_says(cache):
    grid = Grid(SMALL, 0.05)
    landscape, reused = sweep(grid)
    assert not reused and landscape.grid == grid
    assert landscape.path == landscape_path(landscape.key)
    assert landscape.path == cache / "landscapes" / f"{landscape.key}.npz"
    assert landscape.path.exists()
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


def test_a_matching_file_is_reused_and_other_settings_get_their_own(cache):
    grid = Grid(SMALL, 0.05)
    first, _ = sweep(grid)
    again, reused = sweep(grid)
    assert reused and again.key == first.key and again.path == first.path
    other, reused = sweep(grid, Evaluator(body=BodySpec.from_percentile("p95-male")))
    assert not reused and other.key != first.key
    assert Landscape.load(other.path).key == other.key
    assert Landscape.load(first.path).key == first.key
    # Every setting that changes a landscape changes its key.
    for changed in (Evaluator(task=TaskSpec(box_mass_kg=8.0)), Evaluator(task=TaskSpec(gaze="off")),
                    Evaluator(solver="pybullet"),
                    Evaluator(settings=SolverSettings(gaze=2.0)),
                    Evaluator(scoring=ScoringSettings(neutral_tolerance_deg=10.0))):
        assert landscape_key(changed, grid) != first.key
    assert landscape_key(Evaluator(), Grid(SMALL, 0.04)) != first.key


def test_the_key_follows_the_model_source_code(tmp_path, monkeypatch):
    package = tmp_path / "package"
    for name in cache_module.MODEL_SOURCES:
        if name.endswith(".py"):
            (package / name).parent.mkdir(parents=True, exist_ok=True)
            (package / name).write_text("# a module\n")
        else:
            (package / name).mkdir(parents=True)
    (package / "twin" / "solver.py").write_text("WEIGHT = 1.0\n")
    monkeypatch.setattr(cache_module, "PACKAGE", package)
    cache_module.twin_code_version.cache_clear()
    try:
        before = landscape_key(Evaluator(), Grid(SMALL, 0.05))
        (package / "twin" / "solver.py").write_text("WEIGHT = 2.0\n")
        cache_module.twin_code_version.cache_clear()
        assert landscape_key(Evaluator(), Grid(SMALL, 0.05)) != before
    finally:
        cache_module.twin_code_version.cache_clear()


def test_a_corrupted_file_is_detected_and_recomputed(cache, capsys):
    grid = Grid(SMALL, 0.05)
    good, _ = sweep(grid)
    out = good.path
    # A file cut short (a copy interrupted, a full disk) cannot be read.
    out.write_bytes(out.read_bytes()[: out.stat().st_size // 2])
    with pytest.raises(LandscapeError, match="not a readable landscape"):
        Landscape.load(out, good.key)
    capsys.readouterr()
    again, reused = sweep(grid)
    assert not reused
    assert "not a readable landscape" in capsys.readouterr().err  # reported, then swept again
    np.testing.assert_array_equal(again.arrays["reba"], good.arrays["reba"])
    # A well-formed file whose numbers were changed fails its checksum.
    with np.load(out) as data:
        arrays = {name: data[name] for name in data.files}
    arrays["reba"] = arrays["reba"].copy()
    arrays["reba"][0] += 1
    np.savez_compressed(out, **arrays)
    with pytest.raises(LandscapeError, match="checksum"):
        Landscape.load(out, good.key)
    assert not sweep(grid)[1]


def test_an_interrupted_sweep_resumes_without_redoing_chunks(cache, tmp_path, monkeypatch):
    grid = Grid(SMALL, 0.05)  # 100 points
    out = landscape_path(landscape_key(Evaluator(), grid))
    monkeypatch.setattr(sweep_module, "STOP_AFTER_CHUNKS", 2)
    with pytest.raises(SweepInterrupted):
        sweep(grid, chunk=20)
    assert not out.exists()
    parts = out.with_name(out.name + ".parts")
    assert len(list(parts.glob("chunk_*.npz"))) == 2
    monkeypatch.setattr(sweep_module, "STOP_AFTER_CHUNKS", None)
    resumed, reused = sweep(grid, chunk=30)  # another chunk size: the parts still count
    assert not reused and resumed.meta["points_computed"] == grid.size - 40
    assert not parts.exists()
    fresh = fresh_sweep(grid, tmp_path, monkeypatch)
    assert fresh.meta["points_computed"] == grid.size
    for name in fresh.arrays:
        np.testing.assert_array_equal(resumed.arrays[name], fresh.arrays[name], err_msg=name)


@pytest.mark.slow
def test_kill_9_mid_sweep_then_rerun_gives_the_same_file(cache, tmp_path, monkeypatch):
    grid = Grid(SMALL, 0.005)  # 52,111 points: about a second on two processes
    out = landscape_path(landscape_key(Evaluator(), grid))
    script = textwrap.dedent(f"""
        import ergohandover.landscape.sweep as sweep_module
        from ergohandover.landscape import landscape_of
        from ergohandover.twin.evaluate import Evaluator
        from ergohandover.landscape.grid import Grid
        from ergohandover.twin.task import Boundary
        sweep_module.CHUNK_POINTS = 500
        grid = Grid(Boundary({SMALL.x}, {SMALL.y}, {SMALL.z}), 0.005)
        landscape_of(Evaluator(), grid, workers=2, progress=False)
    """)
    proc = subprocess.Popen([sys.executable, "-c", script])  # inherits the test's cache
    parts = out.with_name(out.name + ".parts")
    deadline = time.time() + 120
    while len(list(parts.glob("chunk_*.npz"))) < 2 and time.time() < deadline:
        time.sleep(0.01)
    proc.kill()  # SIGKILL: no clean-up runs, the lock is left to the OS
    proc.wait()
    assert not out.exists() and len(list(parts.glob("chunk_*.npz"))) >= 2
    resumed, reused = sweep(grid)
    assert not reused and resumed.meta["points_computed"] < grid.size
    fresh = fresh_sweep(grid, tmp_path, monkeypatch)
    for name in fresh.arrays:
        np.testing.assert_array_equal(resumed.arrays[name], fresh.arrays[name], err_msg=name)


def test_a_boundary_with_no_feasible_point_is_an_error(cache):
    inside_the_chest = Grid(Boundary((-0.05, 0.05), (1.2, 1.3), (0.0, 0.08)), 0.04)
    with pytest.raises(LandscapeError, match="no feasible point") as error:
        sweep(inside_the_chest)
    assert "male, 1.756 m, 84.3 kg" in str(error.value) and "\n" not in str(error.value)
    out = landscape_path(landscape_key(Evaluator(), inside_the_chest))
    assert not out.exists() and not out.with_name(out.name + ".parts").exists()


def test_statistics_find_the_minimum_and_the_most_symmetric_minimiser(cache):
    landscape, _ = sweep(Grid(SMALL, 0.05))
    stats = statistics(landscape).set_index("score")
    for score in ("paper_postural", "reba", "rula"):
        values = landscape.arrays[score][landscape.feasible]
        row = stats.loc[score]
        assert row["min"] == values.min() and row["n_at_min"] == (values == values.min()).sum()
        assert row["x_min"] <= row["best_x"] <= row["x_max"]
    points = np.array([[0.1, 1, 0.4], [0.0, 1.2, 0.5], [0.0, 1.1, 0.45], [0.0, 1.0, 0.4]])
    assert most_symmetric(points) == 2


@pytest.mark.slow
def test_sweep_and_stats_commands(cache, tmp_path, capsys):
    out = tmp_path / "stats"
    args = ["sweep", "--boundary", "-0.1,0.1,1.0,1.2,0.35,0.5", "--step", "0.05", "--output",
            str(out), "--workers", "1"]
    assert main(args) == 0
    for suffix in ("_stats.csv", "_distribution.csv", "_distribution.png"):
        assert (out / f"landscape{suffix}").exists()
    manifest = json.loads((out / "manifest.json").read_text())
    landscape = Path(manifest["landscape"])
    assert landscape.parent == cache / "landscapes" and landscape.exists()
    capsys.readouterr()
    # landscape-stats reads only, unless --output is given.
    before = sorted(p.name for p in tmp_path.rglob("*"))
    assert main(["landscape-stats", str(landscape)]) == 0
    assert "paper_postural" in capsys.readouterr().out
    assert sorted(p.name for p in tmp_path.rglob("*")) == before
    assert main(["landscape-stats", str(landscape), "--output", str(tmp_path / "s")]) == 0
    assert (tmp_path / "s" / "landscape_stats.csv").exists()
    assert main(args) == 0
    assert "reusing" in capsys.readouterr().err


@pytest.mark.parametrize(("args", "message"), [
    (["--boundary", "0.1,-0.1,1,1.2,0.3,0.5"], "empty or inverted"),
    (["--step", "0"], "--step 0: must be > 0 m"),
    (["--boundary", "elsewhere"], "--boundary elsewhere: not body, paper-code or six numbers"),
])
@pytest.mark.slow
def test_bad_sweep_arguments_exit_2(tmp_path, args, message):
    result = subprocess.run([sys.executable, "-m", "ergohandover.cli", "sweep", "--output",
                             str(tmp_path / "out"), *args], capture_output=True, text=True)
    assert result.returncode == 2 and message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_stats_of_a_corrupted_file_exit_2(tmp_path):
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"not a landscape")
    result = subprocess.run([sys.executable, "-m", "ergohandover.cli", "landscape-stats",
                             str(bad)], capture_output=True, text=True)
    assert result.returncode == 2 and "not a readable landscape" in result.stderr


def test_an_aligned_block_is_the_cube_that_holds_the_cell_cut_at_the_faces():
    grid = Grid(Boundary((0.0, 0.04), (1.0, 1.06), (0.3, 0.32)), 0.01)  # 5 x 7 x 3 cells
    inner = int(np.ravel_multi_index((1, 4, 1), grid.shape))
    block = grid.aligned_block(inner, 2)
    idx = np.stack(np.unravel_index(block, grid.shape), axis=1)
    assert inner in block and len(block) == 8
    assert sorted(map(tuple, idx.tolist())) == [(i, j, k) for i in (0, 1) for j in (4, 5)
                                                 for k in (0, 1)]
    corner = int(np.ravel_multi_index((4, 6, 2), grid.shape))  # at the far faces: cut
    assert grid.aligned_block(corner, 2).tolist() == [corner]
    assert grid.aligned_block(corner, 1).tolist() == [corner]
