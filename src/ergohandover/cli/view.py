"""``ergohandover view``: the handover in a browser — the twin, the robot, the box and the
score landscape, the box moved by hand with the twin re-solved at every move, carries played
back; or, with --export, a recording that opens in a browser without Python."""

from __future__ import annotations

import argparse
import socket
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import ConfigError
from ..io.csv_input import InputError
from ..landscape.stats import optimum
from ..sim import require_display
from ..study.baseline_outputs import record_start, start_numbers
from ..study.baselines import PAPER_STARTS, shortest_distance
from ..study.config import StudyConfig
from .options import (
    add_evaluator_arguments,
    add_grid_arguments,
    add_landscape_argument,
    add_workers_argument,
    evaluator_from_args,
    grid_from_args,
    obtain_landscape,
    writable,
)
from .values import existing_file, number, output_file, whole

DEFAULT_PORT = 8080
RESULTS = Path("results")
RESULTS_BASELINES = RESULTS / "baselines"
INSTALL_HINT = 'pip install -e ".[viewer]"'

DESCRIPTION = f"""\
Start a local viewer and print its address: the worker's twin, the robot holding the box, the
box (drag its gizmo, or type x, y, z in the worker frame: the twin re-solves at every move and
the panel shows the paper's score, REBA, RULA, their components, key joint angles and whether
the robot can hold the box there; infeasible locations are never scored), the landscape's
cells as a coloured point cloud (a slider keeps the scores at or below a value), buttons to the
optimum and each of the paper's starts' shortest-distance locations, and the carries of
--paths played back on a timeline. With --export FILE, writes instead a recording of one
start's baseline comparison (the twin at the optimised location, then at the shortest-distance
one, then the robot's carry) as one HTML page that opens in any browser without Python. Needs
the viewer extra ({INSTALL_HINT})."""


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "view", help="the handover in a browser: move the box, watch the worker",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--host", default="127.0.0.1", metavar="HOST",
                        help="address to serve on (default: 127.0.0.1, this machine only)")
    parser.add_argument("--port", type=whole(1, 65535), default=DEFAULT_PORT, metavar="N",
                        help=f"port to serve on, 1-65535 (default: {DEFAULT_PORT})")
    add_grid_arguments(parser, "handover boundary (where the box may go); with --landscape: "
                       "the landscape's", "grid step [m] of the landscape; with --landscape: "
                       "the landscape's")
    add_evaluator_arguments(parser, solver=False)
    add_landscape_argument(parser)
    parser.add_argument("--paths", type=Path, metavar="DIR",
                        help="a folder of carry path files to play back (default: "
                        f"{RESULTS_BASELINES / 'paths'} when it exists)")
    parser.add_argument("--export", type=output_file, metavar="FILE",
                        help="write a recording (.html) of one start's comparison and carry "
                        "instead of serving")
    parser.add_argument("--start", type=whole(1, len(PAPER_STARTS)), default=1, metavar="K",
                        help="with --export: which of the baselines' starts, 1-"
                        f"{len(PAPER_STARTS)} (default: 1)")
    parser.add_argument("--baselines", type=existing_file, metavar="CSV",
                        help="with --export: the baselines table to record (default: "
                        f"{RESULTS_BASELINES / 'baselines.csv'})")
    parser.add_argument("--seconds", type=number(0, None, "s", above=True), metavar="S",
                        help="stop serving after S seconds (default: until Ctrl-C)")
    parser.add_argument("--gui", action="store_true",
                        help="also show the scene in PyBullet's own window; needs a display "
                        "(DISPLAY or WAYLAND_DISPLAY) (default: the browser only)")
    add_workers_argument(parser, "processes for a landscape sweep")
    parser.set_defaults(run=run)


def viewer_modules():
    """The viewer's modules, or a one-line error naming the extra to install."""
    try:
        from ..viewer import app, recording
    except ImportError as error:
        raise ConfigError(f"ergohandover view needs the viewer extra ({error.name} is "
                          f"missing): {INSTALL_HINT}") from None
    return app, recording


def check_port(host: str, port: int) -> None:
    """A one-line error when ``host:port`` cannot be served (in use, or not this machine's)."""
    with socket.socket() as probe:
        try:
            probe.bind((host, port))
        except OSError as error:
            raise InputError(f"--port {port} on --host {host} cannot be served "
                             f"({error.strerror}); choose another with --port") from None


def named_locations(landscape, evaluator) -> dict[str, np.ndarray]:
    """The optimum and each paper start's shortest-distance location; for the study's worker,
    also the robustness part's headline locations that lie within the boundary (the robust
    optimum, the learned location, the one-size ones, ...)."""
    named = {"optimum (paper score)": optimum(landscape, "paper_postural")[1]}
    for k, start in enumerate(PAPER_STARTS, start=1):
        named[f"shortest distance, start {k}"] = shortest_distance(start,
                                                                   landscape.grid.boundary)
    study = RESULTS / "robustness" / "locations.csv"
    if evaluator == StudyConfig().evaluator() and study.exists():
        b = landscape.grid.boundary
        for name, row in pd.read_csv(study).drop_duplicates("location").set_index(
                "location")[["x", "y", "z"]].iterrows():
            where = row.to_numpy(float)
            if not name.startswith(("nominal", "shortest")) and np.all(
                    (where >= b.lower - 1e-9) & (where <= b.upper + 1e-9)):
                named[f"{name} (study)"] = where
    return named


def export(args, evaluator, recording) -> int:
    """Write one start's recording."""
    table = pd.read_csv(args.baselines or RESULTS_BASELINES / "baselines.csv")
    boundary = grid_from_args(evaluator, args.boundary, args.step).boundary
    html = record_start(table, args.start, boundary, evaluator,
                        args.paths or RESULTS_BASELINES / "paths")
    if html is None:
        raise InputError(f"--start {args.start}: the baselines table has "
                         f"{start_numbers(table).max()} starts")
    written = recording.write_recording(html, writable(args.export))
    print(f"wrote {written} ({len(html) / 1e6:.1f} MB): open it in a browser", file=sys.stderr)
    return 0


def run(args: argparse.Namespace) -> int:
    if args.gui:
        require_display()
    app, recording = viewer_modules()
    evaluator = evaluator_from_args(args)
    if args.export:
        return export(args, evaluator, recording)
    check_port(args.host, args.port)
    landscape, _ = obtain_landscape(args, evaluator)
    paths_dir = args.paths or RESULTS_BASELINES / "paths"
    if args.paths is not None and not args.paths.is_dir():
        raise InputError(f"--paths {args.paths}: no such folder")
    paths = sorted(paths_dir.glob("*.csv")) if paths_dir.is_dir() else []
    server = app.start_server(args.host, args.port)
    # The study's accommodation zone, a layer for its worker and task only.
    zone_file = RESULTS / "accommodation" / "cells.csv"
    zone = pd.read_csv(zone_file) if zone_file.is_file() and \
        evaluator.task == StudyConfig().evaluator().task else None
    viewer = app.HandoverViewer(evaluator, landscape, named_locations(landscape, evaluator),
                                paths, server, gui=args.gui, zone=zone)
    print(f"viewer at http://{args.host}:{args.port} (Ctrl-C to stop)", flush=True)
    try:
        deadline = time.monotonic() + (args.seconds or float("inf"))
        while time.monotonic() < deadline:
            time.sleep(min(0.2, max(deadline - time.monotonic(), 0.0)))
    finally:
        viewer.close()
    return 0
