"""``ergohandover baseline``: the optimised handover location against the paper's
shortest-distance heuristic, from each start point, with the twin's scores and the robot's
feasibility (the paper's Table "Comparison of Optimized and Ergonomically Naive methods")."""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from ..executor import check_workers
from ..io.atomic import atomic_write, atomic_write_csv
from ..io.csv_input import InputError
from ..io.manifest import write_manifest
from ..landscape.cache import Landscape, landscape_key
from ..landscape.grid import DEFAULT_STEP, Grid, parse_boundary
from ..landscape.store import landscape_of
from ..scene.robot import RobotSpec, RobotSpecError
from ..study.baseline_outputs import render, write_paths
from ..study.baselines import PAPER_STARTS, compare, markdown_table
from ..twin.evaluate import Evaluator
from .options import add_evaluator_arguments, evaluator_from_args, run_folder

START = "three finite numbers X,Y,Z in metres, worker frame"
ROBOT_FLAGS = {"distance": "robot-distance", "drive_range": "robot-drive",
               "arm_spacing": "robot-spacing",
               "mount_height": "robot-height"}

DESCRIPTION = """\
For each start point of the box (worker frame, metres: x right, y up, z forward), compare the
landscape's optimised location (lowest paper postural score, the most symmetric among ties)
with the paper's naive one (the boundary point nearest the start). At each location: the
twin's paper postural score, REBA and RULA, and the dual-arm robot's carry of the box from
the start to there, planned with OMPL clear of the robot itself, the box and the worker (per
carry: planning time, path length, waypoints, clearance to the worker; or why it cannot be
served). Writes a CSV, a markdown table beside the paper's numbers and manifest.json (into
--output's folder; default a new runs/baseline/<timestamp>/) and prints the table. The
landscape comes from the landscape cache (swept into it when missing) unless --landscape
names a file."""


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "baseline", help="optimised vs shortest-distance handover locations from start points",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--start", action="append", metavar="X,Y,Z",
                        help="a start point of the box [m], e.g. --start -0.3,0.8,0.9; repeat "
                        "for several (default: the paper's five)")
    parser.add_argument("--boundary", metavar="body|paper-code|X0,X1,Y0,Y1,Z0,Z1",
                        help="handover boundary (default: the landscape's, else paper-code)")
    parser.add_argument("--step", type=float, metavar="S",
                        help=f"grid step [m] (default: the landscape's, else {DEFAULT_STEP})")
    add_evaluator_arguments(parser, solver=False)
    parser.add_argument("--landscape", type=Path, metavar="FILE",
                        help="a landscape .npz (default: the matching one from the landscape "
                        "cache, swept into it when missing)")
    parser.add_argument("--output", type=Path, metavar="FILE",
                        help="CSV to write; the .md table and manifest.json go beside it "
                        "(default: runs/baseline/<timestamp>/baselines.csv)")
    parser.add_argument("--render", type=Path, metavar="DIR",
                        help="also write a PNG per start and location, a contact sheet and a "
                        "GIF per planned carry into DIR (created if needed)")
    parser.add_argument("--paths", type=Path, metavar="DIR",
                        help="also write a CSV per planned carry into DIR: time, the box pose "
                        "(worker frame) and every robot joint by its URDF name; the robot base "
                        "pose (world frame) in the first row (docs/robot.md)")
    parser.add_argument("--seed", type=int, default=0,
                        help="seed of the carry planner (each carry's own is spawned from it; "
                        "default 0)")
    group = parser.add_argument_group("robot (docs/robot.md)")
    defaults = RobotSpec()
    group.add_argument("--robot-distance", type=float, default=defaults.distance, metavar="M",
                       help=f"arm bases in front of the worker with the base driven fully "
                       f"back [m] (default: {defaults.distance})")
    group.add_argument("--robot-drive", type=float, default=defaults.drive_range, metavar="M",
                       help=f"travel of the mobile base toward the worker [m] (default: "
                       f"{defaults.drive_range})")
    group.add_argument("--robot-spacing", type=float, default=defaults.arm_spacing,
                       metavar="M", help=f"distance between the arm bases [m] (default: "
                       f"{defaults.arm_spacing})")
    group.add_argument("--robot-height", type=float, default=defaults.mount_height,
                       metavar="M", help=f"height of the arm bases [m] (default: "
                       f"{defaults.mount_height})")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="processes for a sweep and for planning carries (default: all cores)")
    parser.set_defaults(run=run)


def parse_start(text: str) -> np.ndarray:
    """``X,Y,Z`` -> (3,) [m]; anything else is a one-line InputError."""
    try:
        values = [float(part) for part in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise InputError(f"start = {text!r} is not allowed (expected {START})")
    return np.array(values)


def obtain_landscape(args, evaluator: Evaluator) -> tuple[Landscape, Path]:
    """The given landscape (checked against the flags), or the landscape door's (from the
    cache, swept into it when missing)."""
    body, task = evaluator.body, evaluator.task
    if args.landscape is not None:
        landscape = Landscape.load(args.landscape)
        boundary = (parse_boundary(args.boundary, body, task) if args.boundary
                    else landscape.grid.boundary)
        grid = Grid(boundary, args.step or landscape.grid.step)
        if landscape.key != landscape_key(evaluator, grid):
            raise InputError(f"landscape = '{args.landscape}' was made with other settings "
                             f"(worker, boundary, step or version; key {landscape.key}, "
                             f"expected {landscape_key(evaluator, grid)}); omit --landscape "
                             "to sweep the matching one")
        return landscape, args.landscape
    grid = Grid(parse_boundary(args.boundary or "paper-code", body, task),
                args.step or DEFAULT_STEP)
    print(f"landscape: {grid.describe()}", file=sys.stderr)
    landscape = landscape_of(evaluator, grid, workers=args.workers)
    print(f"landscape: {landscape.path}", file=sys.stderr)
    return landscape, landscape.path


def run(args: argparse.Namespace) -> int:
    started = time.perf_counter()
    check_workers(args.workers)
    if args.seed < 0:
        raise InputError(f"seed = {args.seed} is not allowed (use an integer >= 0)")
    starts = np.array([parse_start(s) for s in args.start]) if args.start else PAPER_STARTS
    try:
        robot = RobotSpec(distance=args.robot_distance, drive_range=args.robot_drive,
                          arm_spacing=args.robot_spacing,
                          mount_height=args.robot_height)
    except RobotSpecError as exc:
        field = str(exc).split(" = ")[0]
        raise InputError(str(exc).replace(field, ROBOT_FLAGS.get(field, field), 1)) from None
    evaluator = evaluator_from_args(args)
    if args.output is not None and not args.output.parent.is_dir():
        raise InputError(f"output = '{args.output}': directory '{args.output.parent}' does "
                         "not exist")
    landscape, source = obtain_landscape(args, evaluator)
    result = compare(starts, landscape, evaluator, robot, seed=args.seed,
                     workers=args.workers)
    output = args.output or run_folder("baseline") / "baselines.csv"
    markdown = markdown_table(result.table)
    atomic_write_csv(result.table, output)
    md_path = atomic_write(output.with_suffix(".md"), lambda h: h.write(markdown))
    pictures = render(result, evaluator, robot, args.render) if args.render else []
    paths = write_paths(result, evaluator, robot, args.paths) if args.paths else []
    write_manifest(output, config={
        "starts": starts.tolist(), "evaluator": dataclasses.asdict(evaluator),
        "robot": dataclasses.asdict(robot), "landscape": str(source),
        "landscape_key": landscape.key, "grid": dataclasses.asdict(landscape.grid)},
        seeds={"planner": args.seed}, wall_time_s=time.perf_counter() - started,
        extra={"outputs": [str(output), str(md_path), *map(str, pictures), *map(str, paths)]})
    print(markdown, end="")
    print(f"wrote {output}, {md_path}", file=sys.stderr)
    return 0
