"""``ergohandover view``: the handover in a browser — the twin, the robot, the box and the
score landscape, the box moved by hand with the twin re-solved at every move, carries played
back; or, with --export, a recording that opens in a browser without Python."""

from __future__ import annotations

import argparse
import errno
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
from ..study.baselines.comparison import PAPER_STARTS, shortest_distance
from ..study.baselines.outputs import record_start, start_numbers
from ..study.config import StudyConfig
from ..study.script import ROOT
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
from .parser import given
from .values import BadValue, existing_file, number, output_file, whole

DEFAULT_PORT = 8080
RESULTS = ROOT / "results"
"""The study's results in the checkout (not the working directory's: the command runs from
anywhere)."""
INSTALL_HINT = 'pip install -e ".[viewer]"'
QUICK_STEP = 0.01
"""The grid step [m] of the landscape shown while the cache lacks the one asked for: a 1 cm
landscape is swept in seconds, the study's 3 mm one (35 times the points) in minutes, and the
cloud thins that one to every third cell (9 mm) anyway (:data:`..viewer.cloud.MAX_POINTS`)."""

DESCRIPTION = f"""\
Start a local viewer and print its address: the worker's twin, the robot holding the box, the
box (drag its gizmo, or type x, y, z in the worker frame: the twin re-solves at every move and
the panel shows the paper's score, REBA, RULA, their components, key joint angles and whether
the robot can hold the box there; infeasible locations are never scored), the landscape's
cells as a coloured point cloud (a slider keeps the scores at or below a value), locations to
move the box to (the optimum, where it opens, and each of the paper's starts' shortest-distance
locations; the chosen one is labelled, a click on a marker chooses it), and the carries of
--paths played back on a timeline. The cloud opens on the cells within one point of the best
score. While the landscape cache lacks the --step landscape and --step is not given, a \
{QUICK_STEP * 100:g} cm
one is swept in seconds and shown instead (said on stderr). With --export FILE, writes instead
a recording of one start's baseline comparison (the twin at the optimised location, then at
the shortest-distance one, then the robot's carry) as one HTML page that opens in any browser
without Python. Needs the viewer extra ({INSTALL_HINT})."""


def existing_folder(text: str) -> Path:
    """A folder that exists (refused while parsing otherwise)."""
    path = Path(text)
    if not path.is_dir():
        raise BadValue(text, "a file, not a folder" if path.exists() else "no such folder")
    return path


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "view", help="the handover in a browser: move the box, watch the worker",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--host", default="127.0.0.1", metavar="HOST",
                        help="address to serve on, one of this machine's (default: "
                        "127.0.0.1, this machine only; 0.0.0.0: every network)")
    parser.add_argument("--port", type=whole(1, 65535), default=DEFAULT_PORT, metavar="N",
                        help=f"port to serve on, 1-65535 (default: {DEFAULT_PORT})")
    add_grid_arguments(parser, "handover boundary (where the box may go); with --landscape: "
                       "the landscape's", "grid step [m] of the landscape, from the landscape "
                       "cache or swept into it before serving (not given: while the cache "
                       f"lacks it, a {QUICK_STEP:g} m one, swept in seconds, is shown instead); "
                       "with --landscape: the landscape's")
    add_evaluator_arguments(parser, solver=False)
    add_landscape_argument(parser)
    parser.add_argument("--results", type=existing_folder, default=RESULTS, metavar="DIR",
                        help="the study's results: its carries, baselines table, headline "
                        "locations and accommodation zone (default: results/ of the "
                        "checkout, from any working directory)")
    parser.add_argument("--paths", type=Path, metavar="DIR",
                        help="a folder of carry path files to play back (default: "
                        "results/baselines/paths, of --results, when it exists)")
    parser.add_argument("--export", type=output_file, metavar="FILE",
                        help="write a recording (.html) of one start's comparison and carry "
                        "instead of serving")
    parser.add_argument("--start", type=whole(1, len(PAPER_STARTS)), default=1, metavar="K",
                        help="with --export: which of the baselines' starts, 1-"
                        f"{len(PAPER_STARTS)} (default: 1)")
    parser.add_argument("--baselines", type=existing_file, metavar="CSV",
                        help="with --export: the baselines table to record (default: "
                        "results/baselines/baselines.csv, of --results)")
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


def check_address(host: str, port: int) -> None:
    """A one-line error when ``host:port`` cannot be served: ``--host`` when the host is not
    one of this machine's addresses, ``--port`` when the port is taken or not allowed."""
    not_ours = InputError(f"--host {host}: not an address this machine can serve (one of its "
                          "own: 127.0.0.1 for this machine only, 0.0.0.0 for every network, "
                          "or a name or address of one of its interfaces)")
    try:
        family, kind, protocol, _, address = socket.getaddrinfo(
            host, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)[0]
    except (socket.gaierror, UnicodeError):
        raise not_ours from None
    with socket.socket(family, kind, protocol) as probe:
        try:
            probe.bind(address)
        except OSError as error:
            if error.errno == errno.EADDRNOTAVAIL:
                raise not_ours from None
            raise InputError(f"--port {port} on --host {host} cannot be served "
                             f"({error.strerror}); choose another with --port") from None


def shown_landscape(args, evaluator):
    """The landscape to show: ``--landscape``'s, else the ``--step`` one from the cache (swept
    into it when ``--step`` was given); while the cache lacks it and ``--step`` was not given,
    a :data:`QUICK_STEP` one (from the cache or swept in seconds), said on stderr with how to
    get the other."""
    from ..landscape.store import cached_landscape, landscape_of

    full = grid_from_args(evaluator, args.boundary, args.step)
    extents = np.asarray(full.boundary.upper) - np.asarray(full.boundary.lower)
    if (args.landscape is not None or "step" in given(args) or full.step >= QUICK_STEP
            or extents.min() < QUICK_STEP or cached_landscape(evaluator, full) is not None):
        return obtain_landscape(args, evaluator)[0]
    quick = grid_from_args(evaluator, args.boundary, QUICK_STEP)
    print(f"landscape: the {full.step * 1000:g} mm landscape ({full.size:,} points) is not in "
          f"the landscape cache: showing a {QUICK_STEP * 100:g} cm one", file=sys.stderr)
    print(f"landscape: {quick.describe()}", file=sys.stderr)
    swept = cached_landscape(evaluator, quick) is None
    began = time.monotonic()
    landscape = landscape_of(evaluator, quick, workers=args.workers)
    took = time.monotonic() - began
    print(f"landscape: {landscape.path}", file=sys.stderr)
    # The full sweep's time, from this one's rate (its pool's start-up included: an upper
    # estimate), so that the user knows what --step costs before asking for it.
    ratio = full.size / quick.size
    cost = (f": up to about {duration(took * ratio)} with --workers {args.workers} here"
            if swept else "")
    print(f"landscape: the {full.step * 1000:g} mm one has {ratio:.0f} times the points{cost}; "
          f"give --step {full.step:g} to sweep it before serving (once: it is kept in the "
          "cache, and shown from there by default)", file=sys.stderr)
    return landscape


def duration(seconds: float) -> str:
    """``seconds`` as a person reads it: 40 s, 6 min, 1.5 h."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def named_locations(landscape, evaluator, results: Path = RESULTS) -> dict[str, np.ndarray]:
    """The optimum and each paper start's shortest-distance location; for the study's worker,
    also the robustness part's headline locations (in ``results``) that lie within the
    boundary (the robust optimum, the learned location, the one-size ones, ...)."""
    named = {"optimum (paper score)": optimum(landscape, "paper_postural")[1]}
    for k, start in enumerate(PAPER_STARTS, start=1):
        named[f"shortest distance, start {k}"] = shortest_distance(start,
                                                                   landscape.grid.boundary)
    study = results / "robustness" / "locations.csv"
    if evaluator == StudyConfig().evaluator() and study.is_file():
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
    table_file = args.baselines or args.results / "baselines" / "baselines.csv"
    if not table_file.is_file():
        raise InputError(f"--results {args.results}: no baselines table ({table_file} does "
                         "not exist); give --baselines CSV, or --results DIR holding "
                         "baselines/baselines.csv (the study's baselines part writes it)")
    table = pd.read_csv(table_file)
    boundary = grid_from_args(evaluator, args.boundary, args.step).boundary
    html = record_start(table, args.start, boundary, evaluator,
                        args.paths or args.results / "baselines" / "paths")
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
    check_address(args.host, args.port)
    if args.paths is not None and not args.paths.is_dir():
        raise InputError(f"--paths {args.paths}: no such folder")
    paths_dir = args.paths or args.results / "baselines" / "paths"
    paths = sorted(paths_dir.glob("*.csv")) if paths_dir.is_dir() else []
    landscape = shown_landscape(args, evaluator)
    server = app.start_server(args.host, args.port)
    # The study's accommodation zone, a layer for its worker and task only.
    zone_file = args.results / "accommodation" / "cells.csv"
    zone = pd.read_csv(zone_file) if zone_file.is_file() and \
        evaluator.task == StudyConfig().evaluator().task else None
    viewer = app.HandoverViewer(evaluator, landscape,
                                named_locations(landscape, evaluator, args.results), paths,
                                server, gui=args.gui, zone=zone)
    where = f"[{args.host}]" if ":" in args.host else args.host  # an IPv6 address's URL form
    print(f"viewer at http://{where}:{args.port} (Ctrl-C to stop)", flush=True)
    try:
        deadline = time.monotonic() + (args.seconds or float("inf"))
        while time.monotonic() < deadline:
            time.sleep(min(0.2, max(deadline - time.monotonic(), 0.0)))
    finally:
        viewer.close()
    return 0
