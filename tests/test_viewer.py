"""``ergohandover view``: the viewer re-solves the twin at every box move, plays carries back,
shows the worker, the robot and a coloured landscape in a real (headless) browser, and exports
a recording that opens without a server. On a fresh clone (an empty landscape cache) it serves
within seconds, opening on the box at the optimum in the worker's hands, and it runs from any
working directory."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from PIL import Image

pytest.importorskip("viser")

from ergohandover.cli import main
from ergohandover.cli.options import grid_from_args
from ergohandover.frames import worker_to_world
from ergohandover.landscape.grid import Grid
from ergohandover.landscape.store import landscape_of
from ergohandover.twin.evaluate import Evaluator, evaluate
from ergohandover.viewer.app import (
    LABEL_CLEARANCE,
    SHOWN_ABOVE_MINIMUM,
    HandoverViewer,
    free_port,
    start_server,
)
from ergohandover.viewer.chromium import DevToolsPage
from ergohandover.viewer.handover import panel_text

ROOT = Path(__file__).resolve().parents[1]
PATHS = ROOT / "results" / "baselines" / "paths"
CHROMIUM = shutil.which("chromium")
needs_browser = pytest.mark.skipif(CHROMIUM is None, reason="headless Chromium is not "
                                   "installed (.ci/run installs Debian's chromium)")
GOOD, BAD = np.array([0.0, 1.02, 0.42]), np.array([0.0, 0.73, 0.31])  # takes it / box in body
SIZE = (1280, 800)
SCENE = (slice(160, 800), slice(0, 930))  # below the notice, left of the GUI panel
TINY = "-0.02,0.02,1.0,1.04,0.4,0.44"  # 14 points a side every 3 mm, 5 every 1 cm
SERVE_S = 30.0
"""On a fresh clone (an empty landscape cache) ``ergohandover view`` serves within this."""


class Browser(DevToolsPage):
    """The viewer's page as a test reads it: waits for its panel, then the scene's fade-in."""

    def __init__(self):
        super().__init__(SIZE)

    def open(self, url: str, ready: str = "<canvas", settle_s: float = 3.0,
             timeout_s: float = 90.0) -> str:
        """Load ``url``, wait until its HTML holds ``ready``, let the scene settle (its meshes
        fade in); the page's HTML."""
        self.navigate(url)
        return self.wait_for(ready, settle_s, timeout_s)

    def wait_for(self, ready: str, settle_s: float = 3.0, timeout_s: float = 90.0) -> str:
        """Wait until the page's HTML holds ``ready``, then ``settle_s``; the HTML."""
        deadline = time.monotonic() + timeout_s
        while ready not in self.html() and time.monotonic() < deadline:
            time.sleep(0.5)
        time.sleep(settle_s)
        return self.html()

    def screenshot(self, path: Path) -> np.ndarray:
        """The page as a PNG at ``path``; its scene's pixels."""
        path.write_bytes(self.png())
        return pixels(path)

    def screenshot_when(self, path: Path, shown, timeout_s: float = 120.0) -> np.ndarray:
        """Screenshots until ``shown(pixels)`` holds (the scene has faded in: slowly, where
        software WebGL shares a busy machine), or the last one at the timeout."""
        deadline = time.monotonic() + timeout_s
        image = self.screenshot(path)
        while not shown(image) and time.monotonic() < deadline:
            time.sleep(1.0)
            image = self.screenshot(path)
        return image


@pytest.fixture
def browser():
    opened = Browser()
    yield opened
    opened.close()


def pixels(path: Path) -> np.ndarray:
    return np.asarray(Image.open(path).convert("RGB")).astype(int)[SCENE]


def shirt(image: np.ndarray) -> np.ndarray:
    """The worker's blue shirt and trousers (also while the client fades the meshes in, when
    they are lighter: blue above red and green, not a particular shade)."""
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    return (b > 150) & (b - r > 60) & (b > g)


def hsv(image: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hue [deg], saturation and value (0-1) of RGB pixels: shading changes a surface's value
    much more than its hue and saturation."""
    high, low = image.max(-1), image.min(-1)
    spread = np.maximum(high - low, 1)
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    hue = np.where(high == r, ((g - b) / spread) % 6,
                   np.where(high == g, (b - r) / spread + 2, (r - g) / spread + 4)) * 60
    return hue, (high - low) / np.maximum(high, 1), high / 255


def cardboard(image: np.ndarray) -> np.ndarray:
    """The box's lit faces: tan, more yellow and more saturated than skin, and shaded, unlike
    the cloud's flat yellow and orange points (so a box buried in the cloud is not counted)."""
    hue, saturation, value = hsv(image)
    return ((hue >= 32) & (hue <= 42) & (saturation >= 0.22) & (saturation <= 0.48)
            & (value >= 0.6) & (value <= 0.93))


def skin(image: np.ndarray) -> np.ndarray:
    """The twin's hands and head."""
    hue, saturation, value = hsv(image)
    return (hue >= 12) & (hue < 28) & (saturation >= 0.2) & (saturation <= 0.45) & (value > 0.5)


def hands_at_the_box(image: np.ndarray, margin: int = 40) -> int:
    """Skin pixels within ``margin`` pixels of the box's (the hands holding it, not the
    head)."""
    rows, columns = np.nonzero(cardboard(image))
    if not len(rows):
        return 0
    return int(skin(image)[max(rows.min() - margin, 0):rows.max() + margin,
                           max(columns.min() - margin, 0):columns.max() + margin].sum())


def scored(image: np.ndarray) -> np.ndarray:
    """The landscape's green-to-red points (saturated, not blue)."""
    return (image.max(-1) - image.min(-1) > 80) & (image[..., 2] < image[..., :2].min(-1) - 30)


@pytest.fixture(scope="module")
def viewer():
    evaluator = Evaluator()
    grid = Grid(_boundary(evaluator), 0.04)
    landscape = landscape_of(evaluator, grid)
    port = free_port()
    named = {"optimum": GOOD, "elsewhere": GOOD + np.array([0.1, 0.05, 0.1])}
    shown = HandoverViewer(evaluator, landscape, named, sorted(PATHS.glob("*.csv")),
                           start_server("127.0.0.1", port))
    shown.port = port
    yield shown
    shown.close()


def _boundary(evaluator):
    from ergohandover.landscape.grid import parse_boundary

    return parse_boundary("paper-code", evaluator.body, evaluator.task)


def test_a_move_re_solves_the_twin_and_the_panel_shows_its_scores(viewer):
    before = {n: h.position.copy() for n, h in viewer.scene.mirror.handles.items()}
    move = viewer.move_to(GOOD)
    expected = evaluate(GOOD[None], viewer.evaluator).iloc[0]
    assert move.feasible and viewer.panel.content == panel_text(move)
    for score, label in (("paper_postural", "paper"), ("reba", "REBA"), ("rula", "RULA")):
        assert f"{label} **{int(expected[score])}**" in viewer.panel.content
    moved = viewer.move_to(GOOD + np.array([0.0, 0.2, 0.1]))
    assert moved.row["left_elbow_flexion"] != move.row["left_elbow_flexion"]
    hand = [n for n in viewer.scene.mirror.handles if n.startswith("/scene/worker/")]
    assert any(np.linalg.norm(viewer.scene.mirror.handles[n].position - before[n]) > 0.01
               for n in hand), "the twin's links moved"
    box = next(n for n in viewer.scene.mirror.handles if n.startswith("/scene/box/"))
    np.testing.assert_allclose(viewer.scene.mirror.handles[box].position,
                               worker_to_world(moved.location), atol=0.15)
    # Where the box would cut the body the twin cannot take it: said, never scored.
    refused = viewer.move_to(BAD)
    assert not refused.feasible and "infeasible" in viewer.panel.content
    assert "paper **" not in viewer.panel.content
    # A typed location outside the boundary is one line and changes nothing.
    assert viewer.move_to([0.0, 3.0, 0.4]) is None
    assert viewer.panel.content.startswith("**refused**: location y = 3")
    assert viewer.panel.content.count("\n") == 0
    np.testing.assert_allclose([f.value for f in viewer.fields], BAD)


def test_the_viewer_opens_on_the_best_cells_with_one_label_on_the_chosen_location(viewer):
    import viser

    values = viewer.landscape.arrays["paper_postural"][viewer.landscape.feasible]
    assert viewer.ceiling.value == values.min() + SHOWN_ABOVE_MINIMUM
    cloud = viewer.cloud("paper_postural")
    assert 0 < (cloud.values <= viewer.ceiling.value).sum() < len(cloud.values)
    # One label in the scene, on the location the dropdown chooses, above the box held there.
    labels = [h for h in viewer.server.scene._handle_from_node_name.values()
              if isinstance(h, viser.LabelHandle)]
    assert labels == [viewer.label]
    lift = np.array([0.0, 0.0, viewer.evaluator.task.box_height / 2 + LABEL_CLEARANCE])
    try:
        for name, location in reversed(viewer.named.items()):
            viewer.target.value = name
            assert viewer.label.text == name
            np.testing.assert_allclose(viewer.label.position, worker_to_world(location) + lift,
                                       atol=1e-6)
    finally:
        viewer.target.value = next(iter(viewer.named))


def test_the_landscape_can_be_coloured_by_the_score_expected_under_posture_error(viewer):
    from scipy import stats

    from ergohandover.study.robustness.config import RobustnessConfig
    from ergohandover.viewer.app import EXPECTED, EXPECTED_SD_DEG

    assert RobustnessConfig().robust_sd == EXPECTED_SD_DEG  # the study's robust SD

    nominal = viewer.cloud("paper_postural")
    viewer.score.value = EXPECTED
    try:
        expected = viewer.clouds.get(EXPECTED)
        assert expected is not None and len(expected.values) == len(nominal.values)
        np.testing.assert_array_equal(expected.points, nominal.points)
        # Error only moves a posture off its band: never below the landscape's minimum, and the
        # ordering of the cells is kept broadly.
        assert expected.values.min() >= nominal.values.min()
        assert stats.spearmanr(expected.values, nominal.values).statistic > 0.5
    finally:
        viewer.score.value = "paper_postural"


def test_the_accommodation_zone_is_a_layer_of_the_cells_that_serve_the_share():
    from ergohandover.viewer.cloud import zone_cloud

    cells = pd.DataFrame({"x": [0.0, 0.1, 0.2], "y": [1.0, 1.0, 1.0], "z": [0.4, 0.4, 0.4],
                          "exact_share": [0.95, 0.5, 0.9], "measured_share": [0.6, 0.2, 0.7]})
    evaluator = Evaluator()
    landscape = landscape_of(evaluator, Grid(_boundary(evaluator), 0.08))
    shown = HandoverViewer(evaluator, landscape, {"optimum": GOOD}, [],
                           start_server("127.0.0.1", free_port()), zone=cells)
    try:
        assert zone_cloud(cells, "exact_share", 0.9).values.tolist() == [0.95, 0.9]
        np.testing.assert_allclose(zone_cloud(cells, "exact_share", 0.9).points,
                                   worker_to_world(cells[["x", "y", "z"]].to_numpy()[[0, 2]]),
                                   atol=1e-6)
        assert len(zone_cloud(cells, "measured_share", 0.9).points) == 0
        assert len(shown.draw_zone().points) == 0  # unticked: nothing drawn
        shown.zone_shown.value = True  # the checkbox draws the layer at the slider's share
        shown.zone_share.value = 0.55
        shown.zone_kind.value = "as measured"
        assert shown.draw_zone().values.tolist() == [0.6, 0.7]
    finally:
        shown.close()


@pytest.mark.skipif(not PATHS.is_dir(), reason="no committed carries")
def test_a_carry_plays_back_its_path(viewer):
    name = "start1_optimised"
    viewer.load_carry(name)
    path = pd.read_csv(PATHS / f"{name}.csv")
    box = next(n for n in viewer.scene.mirror.handles if n.startswith("/scene/box/"))
    robot = [n for n in viewer.scene.mirror.handles if n.startswith("/scene/robot/")]
    viewer.show_time(0.0)
    start = viewer.scene.mirror.handles[box].position.copy()
    arm = {n: viewer.scene.mirror.handles[n].position.copy() for n in robot}
    viewer.show_time(float(path["time"].iloc[-1]))
    end = viewer.scene.mirror.handles[box].position.copy()
    travelled = np.linalg.norm(end - start)
    expected = np.linalg.norm(worker_to_world(path[["box_x", "box_y", "box_z"]].to_numpy()[-1])
                              - worker_to_world(path[["box_x", "box_y", "box_z"]].to_numpy()[0]))
    assert travelled == pytest.approx(expected, abs=1e-6)
    assert any(np.linalg.norm(viewer.scene.mirror.handles[n].position - arm[n]) > 0.05
               for n in robot), "the robot's links moved with the carry"


@pytest.mark.slow
@needs_browser
def test_the_browser_shows_the_worker_the_robot_and_a_coloured_landscape(viewer, browser,
                                                                           tmp_path):
    viewer.move_to(GOOD)
    viewer.point_size.value = 10  # the test's 4 cm landscape is sparse: larger points
    viewer.ceiling.value = viewer.ceiling.max  # every cell, not only the best ones it opens on
    browser.open(f"http://127.0.0.1:{viewer.port}", ready="robot: holds the box here")
    image = browser.screenshot_when(
        tmp_path / "all.png", lambda i: shirt(i).sum() > 2000 and scored(i).sum() > 500)
    assert shirt(image).sum() > 2000, "the worker is on screen"
    assert scored(image).sum() > 500, "coloured landscape points are on screen"
    robot = [h for n, h in viewer.scene.mirror.handles.items() if n.startswith("/scene/robot/")]
    for handle in robot:
        handle.visible = False
    try:
        deadline = time.monotonic() + 30  # the open page gets the change in a frame or two
        changed = 0
        while changed <= 3000 and time.monotonic() < deadline:
            time.sleep(0.5)
            without = browser.screenshot(tmp_path / "no_robot.png")
            changed = int((np.abs(image - without).max(-1) > 40).sum())
    finally:
        for handle in robot:
            handle.visible = True
    assert changed > 3000, "the robot is on screen"
    assert shirt(without).sum() > 2000, "the worker stayed"


@pytest.mark.slow
@needs_browser
def test_a_move_through_the_api_changes_the_score_the_page_shows(viewer, browser):
    viewer.move_to(GOOD)
    first = browser.open(f"http://127.0.0.1:{viewer.port}", ready="paper <strong>")
    viewer.move_to(BAD)
    second = browser.wait_for("infeasible", settle_s=0.5)
    assert "paper <strong>" in first and "infeasible" not in first
    assert "infeasible" in second and "paper <strong>" not in second


@pytest.mark.slow
@needs_browser
@pytest.mark.skipif(not PATHS.is_dir(), reason="no committed carries")
def test_an_exported_recording_opens_in_a_browser_without_the_server(tmp_path, browser,
                                                                     monkeypatch):
    monkeypatch.chdir(tmp_path)  # the study's results are the checkout's, from anywhere
    out = tmp_path / "start1.html"
    assert main(["view", "--export", str(out), "--start", "1"]) == 0
    assert out.stat().st_size > 100_000 and "__VISER_EMBED_DATA__" in out.read_text()[:2_000_000]
    browser.open(out.as_uri())
    shown = browser.screenshot_when(tmp_path / "played.png", lambda i: shirt(i).sum() > 1000)
    assert shirt(shown).sum() > 1000, "the recorded worker is shown"


def test_a_port_in_use_is_one_line_and_exit_2(tmp_path, capsys):
    with socket.socket() as held:
        held.bind(("127.0.0.1", 0))
        held.listen()
        port = held.getsockname()[1]
        assert main(["view", "--port", str(port), "--step", "0.04"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"--port {port}" in err and "Traceback" not in err


def test_an_unknown_landscape_file_is_one_line_and_exit_2(tmp_path, capsys):
    assert main(["view", "--landscape", str(tmp_path / "none.npz")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "none.npz" in err


def test_a_bad_export_start_is_one_line_and_writes_nothing(tmp_path, capsys):
    target = tmp_path / "out" / "x.html"
    assert main(["view", "--export", str(target), "--start", "9"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--start 9" in err
    assert not target.parent.exists()


@pytest.mark.slow
@needs_browser
def test_on_a_fresh_clone_it_serves_in_seconds_showing_the_box_in_the_hands(tmp_path, browser):
    said = tmp_path / "stderr.txt"
    port = free_port()
    began = time.monotonic()
    with said.open("w") as stderr:
        command = subprocess.Popen(
            [sys.executable, "-m", "ergohandover.cli", "view", "--port", str(port), "--seconds",
             "900"], stdout=subprocess.PIPE, stderr=stderr, text=True, cwd=tmp_path,
            env={**os.environ, "ERGOHANDOVER_CACHE": str(tmp_path / "empty_cache")})
    try:
        first = command.stdout.readline()  # the address, once it serves (or nothing: it died)
        served = time.monotonic() - began
        assert first.startswith("viewer at"), said.read_text()[-3000:]
        assert served < SERVE_S, f"served after {served:.1f} s"
        err = said.read_text()
        assert "3 mm landscape (3,261,694 points) is not in the landscape cache: showing a 1 cm " \
               "one" in err and "give --step 0.003 to sweep it" in err
        browser.open(f"http://127.0.0.1:{port}", ready="robot: holds the box here")
        image = browser.screenshot_when(
            tmp_path / "opened.png",
            lambda i: cardboard(i).sum() > 600 and hands_at_the_box(i) > 200)
        assert cardboard(image).sum() > 600, "the box is in view, not buried in the cloud"
        assert hands_at_the_box(image) > 200, "the worker's hands hold it"
        assert shirt(image).sum() > 2000, "the worker is on screen"
    finally:
        command.terminate()
        command.wait()


@pytest.mark.slow
def test_on_an_empty_cache_a_1_cm_landscape_is_shown_until_step_is_given(tmp_path, monkeypatch,
                                                                         capsys):
    cache = tmp_path / "cache"
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(cache))
    monkeypatch.chdir(tmp_path)
    full = grid_from_args(Evaluator(), TINY, 0.003)

    def view(*flags) -> str:
        capsys.readouterr()
        assert main(["view", "--boundary", TINY, "--seconds", "0.1", "--workers", "1",
                     "--port", str(free_port()), *flags]) == 0
        return capsys.readouterr().err

    def cached() -> int:
        return len(list((cache / "landscapes").glob("*.npz")))

    err = view()
    assert f"the 3 mm landscape ({full.size:,} points) is not in the landscape cache: " \
           "showing a 1 cm one" in err
    assert "give --step 0.003 to sweep it before serving" in err and cached() == 1
    # Asked for, the 3 mm one is swept before serving; then it is the one shown by default.
    assert "not in the landscape cache" not in view("--step", "0.003") and cached() == 2
    err = view()
    assert "not in the landscape cache" not in err and full.describe() in err and cached() == 2


@pytest.mark.parametrize("host", ["999.1.1.1", "192.0.2.1", "no-such-host.invalid"])
def test_a_host_this_machine_cannot_serve_is_one_line_naming_it(tmp_path, monkeypatch, capsys,
                                                                host):
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)
    assert main(["view", "--host", host]) == 2
    captured = capsys.readouterr()
    assert captured.err.count("\n") == 1 and captured.out == ""
    assert f"--host {host}: not an address this machine can serve" in captured.err
    assert list(tmp_path.iterdir()) == [], "nothing written, no landscape swept"


def test_results_without_a_baselines_table_is_one_line_and_writes_nothing(tmp_path, capsys):
    target = tmp_path / "out" / "x.html"
    assert main(["view", "--export", str(target), "--results", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"--results {tmp_path}: no baselines table" in err
    assert not target.parent.exists()
    assert main(["view", "--results", str(tmp_path / "none")]) == 2
    assert f"--results {tmp_path / 'none'}: no such folder" in capsys.readouterr().err
