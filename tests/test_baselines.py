"""The shortest-distance and optimised locations, and ``ergohandover baseline`` end to end."""

from __future__ import annotations

import json
import shlex

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from ergohandover.cli import main
from ergohandover.landscape import landscape_of
from ergohandover.landscape.grid import Grid
from ergohandover.landscape.stats import minimisers
from ergohandover.study.baselines.comparison import (
    PAPER_STARTS,
    optimised,
    paper_result,
    shortest_distance,
)
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary

coordinate = st.floats(-3.0, 3.0, allow_nan=False, allow_infinity=False)
TINY = Boundary((-0.05, 0.05), (1.0, 1.2), (0.3, 0.45))


@st.composite
def boundaries(draw):
    lo = [draw(st.floats(-1.0, 1.0)) for _ in range(3)]
    size = [draw(st.floats(0.01, 1.0)) for _ in range(3)]
    return Boundary(*((a, a + s) for a, s in zip(lo, size, strict=True)))


def boundary_samples(boundary: Boundary, rng: np.random.Generator, n: int = 3000) -> np.ndarray:
    """Points of the boundary box: inside, on each face, and its corners."""
    lo, hi = boundary.lower, boundary.upper
    inside = rng.uniform(lo, hi, size=(n, 3))
    faces = []
    for axis in range(3):
        for value in (lo[axis], hi[axis]):
            face = rng.uniform(lo, hi, size=(n // 6, 3))
            face[:, axis] = value
            faces.append(face)
    corners = np.array([[(lo, hi)[k >> i & 1][i] for i in range(3)] for k in range(8)])
    return np.vstack([inside, *faces, corners])


@settings(max_examples=60, deadline=None)
@given(start=st.tuples(coordinate, coordinate, coordinate), boundary=boundaries(),
       seed=st.integers(0, 2**32 - 1))
def test_shortest_distance_is_on_the_boundary_and_no_boundary_point_is_nearer(start, boundary,
                                                                              seed):
    start = np.array(start)
    point = shortest_distance(start, boundary)
    assert np.all(point >= boundary.lower) and np.all(point <= boundary.upper)
    outside = np.any((start < boundary.lower) | (start > boundary.upper))
    if outside:  # on the surface: at least one coordinate on a face
        assert np.any(np.isclose(point, boundary.lower) | np.isclose(point, boundary.upper))
    samples = boundary_samples(boundary, np.random.default_rng(seed))
    nearest = np.linalg.norm(samples - start, axis=1).min()
    assert np.linalg.norm(point - start) <= nearest + 1e-12


@settings(max_examples=40, deadline=None)
@given(boundary=boundaries(), fraction=st.tuples(*[st.floats(0, 1)] * 3))
def test_a_start_inside_the_boundary_is_returned_unchanged(boundary, fraction):
    start = boundary.lower + np.array(fraction) * (boundary.upper - boundary.lower)
    assert np.array_equal(shortest_distance(start, boundary), start)


def test_the_paper_starts_clip_to_the_paper_code_boundary():
    expected = [(0.028, 1.122, 0.6), (0.2, 1.122, 0.6), (-0.2, 1.122, 0.6), (0.028, 0.72, 0.6),
                (0.028, 1.44, 0.6)]
    assert np.allclose(shortest_distance(PAPER_STARTS, Boundary.paper_code()), expected)
    assert paper_result(PAPER_STARTS[3], "shortest_distance") == 7
    assert paper_result(PAPER_STARTS[3], "optimised") == 4
    assert np.isnan(paper_result(np.array([0.0, 1.0, 1.0]), "optimised"))


@pytest.fixture(scope="module")
def tiny_landscape():
    landscape = landscape_of(Evaluator(), Grid(TINY, 0.05), progress=False)
    return landscape, landscape.path


def test_optimised_is_a_most_symmetric_minimiser_of_the_score(tiny_landscape):
    landscape, _ = tiny_landscape
    for score in ("paper_postural", "reba", "rula"):
        best = optimised(landscape, score)
        winners = landscape.grid.coordinates(minimisers(landscape, score))
        assert any(np.allclose(best, w) for w in winners)
        assert abs(best[0]) == pytest.approx(np.abs(winners[:, 0]).min())
    with pytest.raises(ValueError, match="not in the landscape"):
        optimised(landscape, "nonsense")


@pytest.mark.parametrize("text", ["1,2", "1,2,3,4", "a,b,c", "nan,1,1", "1,inf,1", "", "1;2;3"])
def test_bad_start_strings_exit_2_with_one_line(capsys, tmp_path, text):
    out = tmp_path / "b.csv"
    assert main(["baseline", f"--start={text}", "--output", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == (f"ergohandover baseline: error: --start {shlex.quote(text)}: not "
                           "three finite numbers X,Y,Z in metres (worker frame)")
    assert not out.exists()


def test_a_landscape_for_another_worker_is_refused(capsys, tiny_landscape, tmp_path):
    _, path = tiny_landscape
    out = tmp_path / "b.csv"
    code = main(["baseline", "--landscape", str(path), "--percentile", "p5-female",
                 "--output", str(out)])
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert "was made with other settings" in err and len(err.splitlines()) == 1
    assert not out.exists()


@pytest.mark.slow
def test_baseline_writes_csv_markdown_manifest_paths_and_pictures(capsys, tiny_landscape,
                                                                  tmp_path):
    landscape, path = tiny_landscape
    out, pictures, paths = tmp_path / "b.csv", tmp_path / "img", tmp_path / "paths"
    start = "0.0,1.1,0.6"  # just beyond the tiny boundary: a short carry
    assert main(["baseline", "--landscape", str(path), f"--start={start}", "--output", str(out),
                 "--render", str(pictures), "--paths", str(paths), "--workers", "2"]) == 0
    printed = capsys.readouterr().out
    table = pd.read_csv(out, keep_default_na=False)
    assert table["method"].tolist() == ["optimised", "shortest_distance"]
    opt, short = table.iloc[0], table.iloc[1]
    assert np.allclose([opt.x, opt.y, opt.z], optimised(landscape))
    assert np.allclose([short.x, short.y, short.z], [0.0, 1.1, 0.45])
    assert short.distance_m == pytest.approx(0.15)
    for row in (opt, short):  # the twin's scores at exactly that location
        assert row.feasible == 1 and row.paper_postural != "" and row.reba != ""
        # Both carries are planned: the box's path is at least the straight distance, and the
        # robot keeps clear of the worker.
        assert row.robot_feasible == 1 and row.robot_reason == "" and row.robot_handover == 1
        assert row.distance_m - 1e-9 <= row.path_length_m and row.clearance_m > 0.0
        assert row.waypoints >= row.distance_m / 0.02 and row.checks > 0
    markdown = out.with_suffix(".md").read_text()
    assert printed.startswith(markdown) and markdown.count("\n") == 3
    # Then the optimum and the robust optimum under 5 deg of posture error (robust.csv).
    robust = pd.read_csv(tmp_path / "robust.csv")
    assert list(robust["location"].unique()) == ["nominal optimum", "robust optimum"]
    assert printed[len(markdown):].count("\n") == 4 and "robust optimum (" in printed
    assert "| (0.000, 1.100, 0.600) |" in markdown and "waypoints, clearance" in markdown
    manifest = json.loads((tmp_path / "manifest.json").read_text())
    assert manifest["config"]["landscape_key"] == landscape.key
    assert manifest["seeds"] == {"planner": 0}
    names = sorted(p.name for p in pictures.iterdir())
    assert names == ["baseline_sheet.png", "start1_optimised.gif", "start1_optimised.png",
                     "start1_shortest_distance.gif", "start1_shortest_distance.png"]
    gif = Image.open(pictures / "start1_optimised.gif")
    assert gif.n_frames > 3 and (pictures / "start1_optimised.gif").stat().st_size < 3_000_000
    for row, name in ((opt, "start1_optimised.csv"), (short, "start1_shortest_distance.csv")):
        carry = pd.read_csv(paths / name)
        first, last = carry.iloc[0], carry.iloc[-1]
        assert np.allclose([first.box_x, first.box_y, first.box_z], [0.0, 1.1, 0.6])
        assert np.allclose([last.box_x, last.box_y, last.box_z], [row.x, row.y, row.z])
        assert carry["time"].is_monotonic_increasing and len(carry) == row.waypoints
        assert carry[["base_x", "base_yaw"]].iloc[1:].isna().all().all()
        assert first.base_yaw == pytest.approx(np.pi)


@pytest.mark.slow
def test_a_negative_start_is_taken_as_typed(capsys, tiny_landscape, tmp_path):
    _, path = tiny_landscape
    out = tmp_path / "b.csv"
    # The paper's start 3 has a negative x: "--start -0.3,..." must not read as an option.
    assert main(["baseline", "--landscape", str(path), "--start", "-0.3,1.1,0.6",
                 "--output", str(out)]) == 0
    table = pd.read_csv(out)
    assert table[["start_x", "start_y", "start_z"]].iloc[0].tolist() == [-0.3, 1.1, 0.6]
    assert table["x"].iloc[1] == pytest.approx(TINY.x[0])  # the nearest boundary point


def test_a_negative_planner_seed_is_one_line_and_writes_nothing(capsys, tmp_path):
    out = tmp_path / "b.csv"
    assert main(["baseline", "--seed", "-1", "--output", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == "ergohandover baseline: error: --seed -1: must be >= 0"
    assert not out.exists()
