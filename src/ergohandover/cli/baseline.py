"""``ergohandover baseline``: the optimised handover location against the paper's
shortest-distance heuristic, from each start point, with the twin's scores and the robot's
feasibility (the paper's Table "Comparison of Optimized and Ergonomically Naive methods")."""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time

import numpy as np

from ..io.atomic import atomic_write, atomic_write_csv
from ..io.manifest import write_manifest
from ..scene.robot import RobotSpec
from ..sim import require_display
from ..study.baselines.comparison import PAPER_STARTS, compare, markdown_table
from ..study.baselines.outputs import render, write_paths
from ..study.robustness.analysis import recommendations
from ..study.robustness.config import RobustnessConfig
from ..twin.evaluate import Evaluator
from . import defaults
from .evaluate import show_in_window
from .options import (
    add_evaluator_arguments,
    add_grid_arguments,
    add_gui_argument,
    add_landscape_argument,
    add_output_folder_argument,
    add_workers_argument,
    evaluator_from_args,
    field_help,
    obtain_landscape,
    run_folder,
    writable,
)
from .refusals import model
from .values import field_value, number, output_file, point, whole

ROBOT_FLAGS = {"distance": "robot-distance", "drive_range": "robot-drive",
               "arm_spacing": "robot-spacing", "mount_height": "robot-height"}
"""The robot's settings a flag sets: field -> flag."""

DESCRIPTION = """\
For each start point of the box (worker frame, metres: x right, y up, z forward), compare the
landscape's optimised location (lowest paper postural score, the most symmetric among ties)
with the paper's naive one (the boundary point nearest the start). At each location: the
twin's paper postural score, REBA and RULA, and the dual-arm robot's carry of the box from
the start to there, planned with OMPL clear of the robot itself, the box and the worker (per
carry: planning time, path length, waypoints, clearance to the worker; or why it cannot be
served). Writes a CSV, a markdown table beside the paper's numbers and manifest.json (into
--output's folder, created if needed; default a new runs/baseline/<timestamp>/) and prints the
table. With --robust-sd (on by default), also the robust optimum, the location of lowest
expected paper score when every measured posture angle carries that much error, found as the
study finds it, beside the optimum: both scored under that error (robust.csv). The landscape
comes from the landscape cache (swept into it when missing) unless --landscape names a file."""


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "baseline", help="optimised vs shortest-distance handover locations from start points",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--start", action="append", type=point, metavar="X,Y,Z",
                        help="a start point of the box [m], e.g. --start -0.3,0.8,0.9; repeat "
                        f"for several (default: the paper's {len(PAPER_STARTS)})")
    add_grid_arguments(parser, "handover boundary; with --landscape: the landscape's",
                       "grid step [m]; with --landscape: the landscape's")
    add_evaluator_arguments(parser, solver=False)
    add_landscape_argument(parser)
    parser.add_argument("--output", type=output_file, metavar="FILE",
                        help="CSV to write (its folder is created if needed); the .md table and "
                        "manifest.json go beside it (default: "
                        "runs/baseline/<timestamp>/baselines.csv)")
    add_output_folder_argument(parser, "also write a PNG per start and location, a contact "
                               "sheet and a GIF per planned carry into DIR (created if needed)",
                               "--render")
    add_output_folder_argument(parser, "also write a CSV per planned carry into DIR (created "
                               "if needed): time, the box pose (worker frame) and every robot "
                               "joint by its URDF name; the robot base pose (world frame) in the "
                               "first row (docs/robot.md)", "--paths")
    parser.add_argument("--seed", type=whole(0), default=defaults.SEED, metavar="K",
                        help="seed of the carry planner, from which each carry's own is "
                        f"spawned (default: {defaults.SEED})")
    group = parser.add_argument_group("robot (docs/robot.md)")
    fields = {f.name: f for f in dataclasses.fields(RobotSpec)}
    for name, flag in ROBOT_FLAGS.items():
        field = fields[name]
        group.add_argument(f"--{flag}", dest=name, type=field_value(field),
                           default=field.default, metavar="M",
                           help=field_help(field, field.default))
    parser.add_argument("--robust-sd", type=number(0, None, "deg"), default=defaults.ANGLE_SD,
                        metavar="DEG", help="also find the robust optimum under this SD of "
                        "error on every measured angle [deg] (the study's search and seed), and "
                        "write both optima's scores under it to robust.csv beside --output; 0 "
                        f"skips it (default: {defaults.ANGLE_SD:g})")
    add_gui_argument(parser, "the first start's optimised location: the worker in its solved "
                     "posture holding the box there, the robot at the end of its carry (or "
                     "holding it there, if the carry was not planned)")
    add_workers_argument(parser, "processes for a sweep, for planning carries and for the "
                         "pictures")
    parser.set_defaults(run=run)


def robust_lines(robust) -> str:
    """The two optima under posture error, a line each (paper score, REBA, RULA)."""
    sd = robust["angle_sd_deg"].iloc[0]
    lines = [f"\nunder {sd:g} deg of posture error (score without error -> expected):"]
    for name, rows in robust.groupby("location", sort=False):
        first = rows.iloc[0]
        scores = ", ".join(f"{r.score} {r.nominal} -> {r.mean:.2f}" for r in rows.itertuples())
        lines.append(f"  {name} ({first.x:.3f}, {first.y:.3f}, {first.z:.3f}): {scores}")
    return "\n".join(lines) + "\n"


def show_first_optimum(result, evaluator: Evaluator, robot: RobotSpec) -> None:
    """PyBullet's window at the first start's optimised location (:func:`show_in_window`),
    the robot where its carry ended (else its first hold there)."""
    i = result.table["method"].tolist().index("optimised")
    row, plan = result.table.iloc[i], result.plans[i]
    location = row[["x", "y", "z"]].to_numpy(float)
    posture = np.asarray(result.postures[i].q)
    if not plan.ok:
        show_in_window(evaluator, location, posture, robot)
        return
    end = plan.waypoints[-1]
    show_in_window(evaluator, location, posture, robot, end.q, end.lift)


def run(args: argparse.Namespace) -> int:
    if args.gui:  # before any work: without a display nothing is swept, computed or written
        require_display("--gui")
    started = time.perf_counter()
    starts = np.array(args.start) if args.start else PAPER_STARTS
    robot = model(RobotSpec, **{name: getattr(args, name) for name in ROBOT_FLAGS})
    evaluator = evaluator_from_args(args)
    landscape, source = obtain_landscape(args, evaluator)
    result = compare(starts, landscape, evaluator, robot, seed=args.seed,
                     workers=args.workers)
    robust = None
    if args.robust_sd > 0:
        print(f"robust optimum at {args.robust_sd:g} deg of posture error", file=sys.stderr)
        robust = recommendations(landscape, evaluator,
                                 RobustnessConfig(robust_sd=args.robust_sd), args.workers)
    output = writable(args.output) if args.output else run_folder("baseline") / "baselines.csv"
    markdown = markdown_table(result.table)
    atomic_write_csv(result.table, output)
    md_path = atomic_write(output.with_suffix(".md"), lambda h: h.write(markdown))
    written = [output, md_path]
    if robust is not None:
        written.append(atomic_write_csv(robust, output.with_name("robust.csv")))
    pictures = (render(result, evaluator, robot, args.render, args.workers) if args.render
                else [])
    paths = write_paths(result, evaluator, robot, args.paths) if args.paths else []
    write_manifest(output, config={
        "starts": starts.tolist(), "evaluator": dataclasses.asdict(evaluator),
        "robot": dataclasses.asdict(robot), "landscape": str(source),
        "landscape_key": landscape.key, "grid": dataclasses.asdict(landscape.grid)},
        seeds={"planner": args.seed}, wall_time_s=time.perf_counter() - started,
        extra={"outputs": [*map(str, written), *map(str, pictures), *map(str, paths)],
               "robust_sd_deg": args.robust_sd})
    print(markdown, end="")
    if robust is not None:
        print(robust_lines(robust), end="")
    print(f"wrote {', '.join(map(str, written))}", file=sys.stderr)
    if args.gui:
        show_first_optimum(result, evaluator, robot)
    return 0
