"""``ergohandover view``'s browser viewer: move the box and watch the worker, the landscape in
space, named locations to jump to, carries played back.

The GUI calls :class:`.handover.HandoverScene` under one lock (PyBullet's client is not
thread-safe, and viser runs each callback in a thread of its own).
"""

from __future__ import annotations

import contextlib
import io
import socket
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import viser

from ..errors import ConfigError
from ..frames import worker_to_world, world_to_worker
from ..landscape import Landscape
from ..scene.world import WorkerPosture
from ..twin.evaluate import Evaluator
from .cloud import colours, expected_cloud, landscape_cloud, share_colours, zone_cloud
from .handover import SCORES, HandoverScene, panel_text, read_path

PLAYBACK_FPS = 20
EXPECTED_SD_DEG = 5.0
"""The posture error of the expected-score colouring: the study's robust SD
(``RobustnessConfig.robust_sd``, which the study layer above owns; a test keeps them equal)."""
EXPECTED = f"expected paper_postural ({EXPECTED_SD_DEG:g} deg error)"
"""The colouring by the paper score expected under that error (computed when first chosen:
the twin at every shown cell)."""
# World frame (worker at the origin facing +x, left +y): from the worker's left, above, so that the
# worker, the box in their hands and the robot across it are in view, clear of the GUI panel on
# the right.
CAMERA = {"eye": (0.95, 2.1, 1.7), "target": (0.25, -0.05, 0.95)}
SHOWN_ABOVE_MINIMUM = 1
"""The cloud first shows the cells within this many points of the landscape's best paper
score: the region worth handing over in, thin enough that the box and the hands inside it stay
in view (every cell's point would bury them)."""
LABEL_CLEARANCE = 0.03
"""The chosen location's label stands this far [m] above the top face of a box held there, so
that it names the location without covering the box or the hands."""


def free_port() -> int:
    """A local port nobody listens on (for a server nobody is told about: a recording's, a
    benchmark's, a test's)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def start_server(host: str, port: int) -> viser.ViserServer:
    """A viser server on ``host:port``, without its banner on standard output."""
    with contextlib.redirect_stdout(io.StringIO()):
        return viser.ViserServer(host=host, port=port, verbose=False)


class HandoverViewer:
    """The viewer: a viser server, the handover scene and its GUI.

    Args:
        evaluator: the worker and scoring.
        landscape: the landscape to show as a cloud (its boundary bounds the box's moves).
        named: name -> worker-frame location (3,) [m] of locations to jump to.
        paths: carry path files to play back.
        server: the viser server (:func:`start_server`).
        zone: the study's accommodation cells (results/accommodation/cells.csv) to show as a
            layer, or None.
        gui: also show the scene in PyBullet's own window (needs a display).
    """

    def __init__(self, evaluator: Evaluator, landscape: Landscape,
                 named: dict[str, np.ndarray], paths: list[Path], server, gui: bool = False,
                 zone: pd.DataFrame | None = None):
        self.server, self.landscape, self.named, self.zone = server, landscape, named, zone
        server.initial_camera.position = CAMERA["eye"]
        server.initial_camera.look_at = CAMERA["target"]
        self.lock = threading.RLock()
        self.syncing = False  # our own updates of the fields and gizmo: not a user's move
        self.scene = HandoverScene(evaluator, landscape.grid.boundary, server, gui=gui)
        self.evaluator, self.paths = evaluator, {p.stem: p for p in paths}
        self.carry: pd.DataFrame | None = None
        self.clouds = {}  # colouring -> its cloud, made when first shown
        self.carry_posture: WorkerPosture | None = None
        self.playing = False
        controls = server.gui
        start = next(iter(named.values()))
        with controls.add_folder("box (worker frame, m)"):
            b = landscape.grid.boundary
            self.fields = [controls.add_number(axis, float(v), min=float(lo), max=float(hi),
                                          step=0.001)
                           for axis, v, lo, hi in zip("xyz", start, b.lower, b.upper,
                                                      strict=True)]
        self.panel = controls.add_markdown("")
        self.gizmo = server.scene.add_transform_controls(
            "/box_gizmo", scale=0.25, disable_rotations=True,
            position=tuple(worker_to_world(start)))
        self._cloud_gui(controls)
        if zone is not None:
            self._zone_gui(controls)
        self._jump_gui(controls)
        self._carry_gui(controls)
        for field in self.fields:
            field.on_update(lambda _: self.syncing or self.move_to([f.value for f in self.fields]))
        self.gizmo.on_update(lambda _: self.syncing or self.move_to(world_to_worker(
            np.asarray(self.gizmo.position)), from_gizmo=True))
        self.move_to(start)

    # --- the box ---------------------------------------------------------------------------
    def move_to(self, location, from_gizmo: bool = False):
        """Move the box to ``location`` (worker frame [m]); a location the viewer refuses is
        one line in the panel and changes nothing."""
        location = np.asarray(location, dtype=float)
        if from_gizmo:  # a drag may overshoot: the box stops at the boundary
            b = self.landscape.grid.boundary
            location = np.clip(location, b.lower, b.upper)
        with self.lock:
            try:
                move = self.scene.move(location)
            except ConfigError as error:
                self.panel.content = f"**refused**: {error}"
                return None
            self.panel.content = panel_text(move)
            self.syncing = True
            try:
                for field, value in zip(self.fields, move.location, strict=True):
                    if abs(field.value - value) > 5e-4:
                        field.value = float(value)
                if not from_gizmo:
                    self.gizmo.position = tuple(worker_to_world(move.location))
            finally:
                self.syncing = False
        return move

    # --- the landscape ---------------------------------------------------------------------
    def _cloud_gui(self, gui) -> None:
        with gui.add_folder("landscape"):
            self.score = gui.add_dropdown("colour by", (*SCORES, EXPECTED),
                                          initial_value="paper_postural")
            values = self.landscape.arrays["paper_postural"][self.landscape.feasible]
            low = int(values.min())
            high = max(int(values.max()), low + 1)  # a slider needs a range: one score too
            self.ceiling = gui.add_slider("show scores <=", low, high, 1,
                                          min(low + SHOWN_ABOVE_MINIMUM, high))
            self.point_size = gui.add_slider("point size [mm]", 1, 10, 1, 4)
        for control in (self.score, self.ceiling, self.point_size):
            control.on_update(lambda _: self.draw_cloud())
        self.draw_cloud()

    def cloud(self, score: str):
        """The cloud coloured by ``score`` (each made once: the slider only filters it)."""
        if score not in self.clouds:
            if score == EXPECTED:
                with self.lock:  # the twin is solved at every shown cell
                    self.clouds[score] = expected_cloud(self.cloud("paper_postural"),
                                                        self.evaluator, EXPECTED_SD_DEG)
            else:
                self.clouds[score] = landscape_cloud(self.landscape, score)
        return self.clouds[score]

    def draw_cloud(self) -> None:
        """The landscape's cells scoring at most the slider's value, coloured by the score."""
        cloud = self.cloud(self.score.value)
        keep = cloud.values <= self.ceiling.value
        low, high = cloud.values.min(), cloud.values.max()
        self.server.scene.add_point_cloud(
            "/landscape", cloud.points[keep], colours(cloud.values[keep], low, high),
            point_size=self.point_size.value / 1000, point_shape="circle")

    # --- the workforce's accommodation zone --------------------------------------------------
    def _zone_gui(self, gui) -> None:
        with gui.add_folder("workforce (accommodation zone)"):
            self.zone_shown = gui.add_checkbox("show", False)
            self.zone_kind = gui.add_dropdown("suited", ("error-free", "as measured"),
                                              initial_value="error-free")
            self.zone_share = gui.add_slider("share at least", 0.0, 1.0, 0.05, 0.9)
        for control in (self.zone_shown, self.zone_kind, self.zone_share):
            control.on_update(lambda _: self.draw_zone())

    def draw_zone(self):
        """The grid points whose share of the workforce suited reaches the slider, coloured by
        that share; nothing while unticked. Returns the cloud drawn."""
        column = "exact_share" if self.zone_kind.value == "error-free" else "measured_share"
        shown = zone_cloud(self.zone, column, self.zone_share.value if self.zone_shown.value
                           else np.inf)
        self.server.scene.add_point_cloud(
            "/zone", shown.points, share_colours(shown.values), point_size=0.012,
            point_shape="square")
        return shown

    # --- named locations -------------------------------------------------------------------
    def _jump_gui(self, gui) -> None:
        with gui.add_folder("go to"):
            self.target = gui.add_dropdown("location", tuple(self.named))
            button = gui.add_button("move the box there")
        button.on_click(lambda _: self.move_to(self.named[self.target.value]))
        # One label, on the chosen location: the study's named locations lie within centimetres
        # of one another (its optima, the learned one, the one-size ones all hug the box), so a
        # label on each would cover the others from every viewpoint. The dropdown lists them
        # all; clicking a marker chooses it.
        for k, (name, location) in enumerate(self.named.items()):
            marker = self.server.scene.add_icosphere(
                f"/named/{k}", radius=0.012, color=(40, 90, 220),
                position=tuple(worker_to_world(location)))
            marker.on_click(lambda _, name=name: setattr(self.target, "value", name))
        self.label = self.server.scene.add_label("/named_label", "", anchor="bottom-center")
        self.label_lift = self.evaluator.task.box_height / 2 + LABEL_CLEARANCE
        self.target.on_update(lambda _: self.show_label())
        self.show_label()

    def show_label(self) -> None:
        """The label on the location chosen in the dropdown."""
        self.label.text = self.target.value
        self.label.position = tuple(worker_to_world(self.named[self.target.value])
                                    + np.array([0.0, 0.0, self.label_lift]))

    # --- carries ---------------------------------------------------------------------------
    def _carry_gui(self, gui) -> None:
        if not self.paths:
            return
        with gui.add_folder("carries"):
            self.carry_name = gui.add_dropdown("path file", tuple(self.paths))
            load = gui.add_button("load")
            self.play_button = gui.add_button("play / pause")
            self.timeline = gui.add_slider("time [s]", 0.0, 1.0, 0.01, 0.0)
        load.on_click(lambda _: self.load_carry(self.carry_name.value))
        self.play_button.on_click(lambda _: self.toggle_play())
        self.timeline.on_update(lambda _: self.show_time(self.timeline.value))

    def load_carry(self, name: str) -> None:
        """Load a path file: the timeline spans it; the worker takes the box at its end."""
        table = read_path(self.paths[name])
        with self.lock:
            self.carry = table
            self.carry_posture = self.scene.handover_posture(table)
        self.timeline.max = float(table["time"].iloc[-1])
        self.timeline.value = 0.0
        self.show_time(0.0)

    def show_time(self, t: float) -> None:
        """The carry at time ``t`` [s]."""
        if self.carry is None:
            return
        with self.lock:
            self.scene.show_time(self.carry, t, self.carry_posture)

    def toggle_play(self) -> None:
        if self.carry is None:
            return
        self.playing = not self.playing
        if self.playing:
            threading.Thread(target=self._play, daemon=True).start()

    def _play(self) -> None:
        end = float(self.carry["time"].iloc[-1])
        while self.playing:
            t = self.timeline.value + 1 / PLAYBACK_FPS
            self.timeline.value = 0.0 if t > end + 1e-9 else round(t, 3)
            time.sleep(1 / PLAYBACK_FPS)

    def close(self) -> None:
        self.playing = False
        with contextlib.redirect_stdout(io.StringIO()):  # viser's "server stopped"
            self.server.stop()
        self.scene.close()
