"""``ergohandover sweep`` and ``ergohandover landscape-stats``: the exhaustive landscape."""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import time
from pathlib import Path

from ..io.csv_input import InputError
from ..landscape.grid import DEFAULT_STEP, Grid, parse_boundary
from ..landscape.stats import write_statistics
from ..landscape.sweep import Landscape, landscape_key, sweep
from ..study.manifest import write_manifest
from ..twin.evaluate import SOLVERS, Evaluator
from ..twin.task import TaskSpec
from .options import add_body_arguments, body_from_args

DEFAULT_DIR = Path("results") / "landscapes"


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "sweep", help="evaluate every grid point of a boundary (the exhaustive landscape)",
        description="Evaluate every point of the grid (resumable, cached by a hash of every "
        "setting) and write a compact landscape file, its statistics and distribution figure.")
    parser.add_argument("--boundary", default="body", metavar="body|paper-code|X0,X1,Y0,Y1,Z0,Z1",
                        help="the paper's body-derived boundary, the published code's numbers, "
                        "or explicit ranges in metres, worker frame; write --boundary=-0.2,... "
                        "when it starts with a minus (default: body)")
    parser.add_argument("--step", type=float, default=DEFAULT_STEP, metavar="S",
                        help=f"grid step [m] (default: {DEFAULT_STEP}, the paper's)")
    add_body_arguments(parser)
    parser.add_argument("--solver", choices=SOLVERS, default="numpy",
                        help="posture solver (default: numpy)")
    parser.add_argument("--output", type=Path, metavar="FILE",
                        help="landscape file (.npz); default results/landscapes/<key>/"
                        "landscape.npz")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="processes (default: all cores)")
    parser.set_defaults(run=run_sweep)

    stats = subparsers.add_parser(
        "landscape-stats", help="statistics and distribution figure of a landscape file",
        description="Per score: the distribution over feasible points, the minimum, the "
        "minimising locations (count, bounding box, most symmetric one), the feasible fraction.")
    stats.add_argument("file", type=Path, help="a landscape .npz written by sweep")
    stats.set_defaults(run=run_stats)


def run_sweep(args: argparse.Namespace) -> int:
    if args.workers < 1:
        raise InputError(f"workers = {args.workers} is outside the valid range (at least 1)")
    body, task = body_from_args(args), TaskSpec()
    grid = Grid(parse_boundary(args.boundary, body, task), args.step)
    evaluator = Evaluator(body, task, args.solver)
    key = landscape_key(evaluator, grid)
    output = args.output or DEFAULT_DIR / key / "landscape.npz"
    output.parent.mkdir(parents=True, exist_ok=True)
    print(grid.describe(), file=sys.stderr)
    start = time.perf_counter()
    landscape, reused = sweep(grid, evaluator, output, workers=args.workers)
    elapsed = time.perf_counter() - start
    if reused:
        print(f"reusing {output} (key {key}: same body, task, boundary, step and settings)",
              file=sys.stderr)
    else:
        rate = landscape.meta["points_computed"] / max(landscape.meta["seconds"], 1e-9)
        print(f"swept {grid.size:,} points in {elapsed:.1f} s ({rate:,.0f} points/s computed "
              f"this run) -> {output}", file=sys.stderr)
        write_manifest(output, config={"evaluator": dataclasses.asdict(evaluator),
                                       "grid": dataclasses.asdict(grid), "key": key},
                       seeds={}, wall_time_s=elapsed,
                       extra={"points_per_s": round(rate, 1),
                              "points_computed": landscape.meta["points_computed"]})
    report(landscape, output)
    return 0


def report(landscape: Landscape, path: Path) -> None:
    stats, paths = write_statistics(landscape, path.with_suffix(""))
    shown = stats[["score", "min", "n_at_min", "fraction_at_min", "feasible_fraction",
                   "best_x", "best_y", "best_z"]]
    print(shown.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    for p in paths:
        print(f"wrote {p}", file=sys.stderr)


def run_stats(args: argparse.Namespace) -> int:
    report(Landscape.load(args.file), args.file)
    return 0
