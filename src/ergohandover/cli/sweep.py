"""``ergohandover sweep`` and ``ergohandover landscape-stats``: the exhaustive landscape."""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import time
from pathlib import Path

from ..executor import check_workers
from ..io.csv_input import InputError
from ..io.manifest import write_manifest
from ..landscape import Landscape, landscapes_of
from ..landscape.grid import DEFAULT_STEP, Grid, parse_boundary
from ..landscape.stats import statistics, write_statistics
from .options import (
    add_evaluator_arguments,
    evaluator_from_args,
    run_folder,
)


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "sweep", help="evaluate every grid point of a boundary (the exhaustive landscape)",
        description="Evaluate every point of the grid into the landscape cache (resumable; "
        "reused when the same body, task, boundary, step, settings and model code were swept "
        "before) and write its statistics and distribution figure.")
    parser.add_argument("--boundary", default="body", metavar="body|paper-code|X0,X1,Y0,Y1,Z0,Z1",
                        help="the paper's body-derived boundary, the published code's numbers, "
                        "or explicit ranges in metres, worker frame (default: body)")
    parser.add_argument("--step", type=float, default=DEFAULT_STEP, metavar="S",
                        help=f"grid step [m] (default: {DEFAULT_STEP}, the paper's)")
    add_evaluator_arguments(parser)
    parser.add_argument("--output", type=Path, metavar="DIR",
                        help="folder for the statistics, figure and manifest.json (default: a "
                        "new runs/sweep/<timestamp>/); the landscape itself goes to the cache")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="processes (default: all cores)")
    parser.set_defaults(run=run_sweep)

    stats = subparsers.add_parser(
        "landscape-stats", help="statistics of a landscape file (prints; writes with --output)",
        description="Per score: the distribution over feasible points, the minimum, the "
        "minimising locations (count, bounding box, most symmetric one), the feasible fraction. "
        "Prints them; with --output also writes the CSVs and the distribution figure.")
    stats.add_argument("file", type=Path, help="a landscape .npz (the path `sweep` prints)")
    stats.add_argument("--output", type=Path, metavar="DIR",
                       help="also write landscape_stats.csv, landscape_distribution.csv and "
                       ".png into DIR (created if needed)")
    stats.set_defaults(run=run_stats)


def run_sweep(args: argparse.Namespace) -> int:
    check_workers(args.workers)
    evaluator = evaluator_from_args(args)
    grid = Grid(parse_boundary(args.boundary, evaluator.body, evaluator.task), args.step)
    if args.output is not None and args.output.exists() and not args.output.is_dir():
        raise InputError(f"output = '{args.output}' is a file (expected a directory)")
    print(grid.describe(), file=sys.stderr)
    start = time.perf_counter()
    # The door that also says whether the landscape was read from the cache (also when another
    # process swept it while this one waited) or computed here.
    [finished] = landscapes_of([evaluator], grid, workers=args.workers)
    landscape, reused = finished.landscape, finished.reused
    elapsed = time.perf_counter() - start
    rate = None
    if reused:
        print(f"reusing {landscape.path} (same body, task, boundary, step, settings and "
              "model code)", file=sys.stderr)
    else:
        rate = landscape.meta["points_computed"] / max(landscape.meta["seconds"], 1e-9)
        print(f"swept {grid.size:,} points in {elapsed:.1f} s ({rate:,.0f} points/s computed "
              f"this run) -> {landscape.path}", file=sys.stderr)
    folder = args.output or run_folder("sweep")
    folder.mkdir(parents=True, exist_ok=True)
    paths = report(landscape, folder)
    write_manifest(folder, config={"evaluator": dataclasses.asdict(evaluator),
                                   "grid": dataclasses.asdict(grid), "key": landscape.key},
                   seeds={}, wall_time_s=elapsed,
                   extra={"landscape": str(landscape.path), "reused": reused,
                          "points_per_s": None if rate is None else round(rate, 1),
                          "outputs": [str(p) for p in paths]})
    return 0


def report(landscape: Landscape, folder: Path | None) -> list[Path]:
    """Print the statistics; write them (and the figure) into ``folder`` if given."""
    if folder is None:
        stats, paths = statistics(landscape), []
    else:
        stats, paths = write_statistics(landscape, folder / "landscape")
    shown = stats[["score", "min", "n_at_min", "fraction_at_min", "feasible_fraction",
                   "best_x", "best_y", "best_z"]]
    print(shown.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    for p in paths:
        print(f"wrote {p}", file=sys.stderr)
    return paths


def run_stats(args: argparse.Namespace) -> int:
    landscape = Landscape.load(args.file)
    if args.output is not None:
        args.output.mkdir(parents=True, exist_ok=True)
    report(landscape, args.output)
    return 0
