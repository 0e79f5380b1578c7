"""``ergohandover sweep`` and ``ergohandover landscape-stats``: the exhaustive landscape."""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

from ..io.csv_input import InputError
from ..io.manifest import write_manifest
from ..landscape import Landscape, landscapes_of
from ..landscape.stats import statistics, write_statistics
from .options import (
    add_evaluator_arguments,
    add_grid_arguments,
    add_output_folder_argument,
    add_workers_argument,
    add_yes_argument,
    check_work,
    evaluator_from_args,
    grid_from_args,
    run_folder,
)
from .refusals import read_landscape
from .values import existing_file, field_value

MAX_POINTS = 20_000_000
"""Points a sweep runs without --yes (the paper's 3 mm grid has 3.26 M)."""


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "sweep", help="evaluate every grid point of a boundary (the exhaustive landscape)",
        description="Evaluate every point of the grid into the landscape cache (resumable; "
        "reused when the same body, task, boundary, step, settings and model code were swept "
        "before, by a command or the study) and write its statistics and distribution figure.")
    add_grid_arguments(parser, "the published code's boundary, the paper's body-derived one, "
                       "or explicit ranges in metres, worker frame", "grid step [m]")
    add_evaluator_arguments(parser)
    from ..twin.solver import SolverSettings

    warm_start = next(f for f in dataclasses.fields(SolverSettings) if f.name == "warm_start")
    parser.add_argument("--warm-start", type=field_value(warm_start), default=warm_start.default,
                        metavar="|".join(warm_start.metadata["choices"]),
                        help="where each location's solve starts: the coarse lattice (the "
                        "study's solve; the default) or today's solves every 6 mm, "
                        "interpolated (faster, and the default's scores at nearly every "
                        "point: python experiments/bench_sweep.py --compare measures both on "
                        "this machine; a landscape of its own)")
    add_output_folder_argument(parser, "folder for the statistics, figure and manifest.json "
                               "(created if needed; default: a new runs/sweep/<timestamp>/); "
                               "the landscape itself goes to the cache")
    add_workers_argument(parser, "processes")
    add_yes_argument(parser, f"{MAX_POINTS:,} points")
    parser.set_defaults(run=run_sweep)

    stats = subparsers.add_parser(
        "landscape-stats", help="statistics of a landscape file (prints; writes with --output)",
        description="Per score: the distribution over feasible points, the minimum, the "
        "minimising locations (count, bounding box, most symmetric one), the feasible fraction. "
        "Prints them; with --output also writes the CSVs and the distribution figure.")
    stats.add_argument("file", type=existing_file,
                       help="a landscape .npz (the path `sweep` prints)")
    add_output_folder_argument(stats, "also write landscape_stats.csv, "
                               "landscape_distribution.csv and .png into DIR (created if "
                               "needed)")
    stats.set_defaults(run=run_stats)


def sweep_cost(evaluator, grid) -> tuple[float, float]:
    """Seconds per point on one core, measured on 2,048 of the grid's points after the
    solver's set-up, and bytes per point the landscape holds."""
    from ..landscape.sweep import ANGLES, SCORES
    from ..twin.evaluate import evaluate_arrays

    points = grid.points(0, 2048)
    evaluate_arrays(points[:64], evaluator)  # the solver's set-up, not a point's cost
    start = time.perf_counter()
    evaluate_arrays(points, evaluator)
    # A landscape keeps flags and scores as one byte, angles as four; held twice while saved.
    per_point = 2 * (1 + len(SCORES) + 4 * len(ANGLES))
    return (time.perf_counter() - start) / len(points), per_point


def run_sweep(args: argparse.Namespace) -> int:
    evaluator = evaluator_from_args(args)
    if args.warm_start == "fine" and evaluator.solver != "whole-body":
        raise InputError(f"--warm-start fine is not allowed with --solver {evaluator.solver} "
                         "(it interpolates the whole-body solver's postures)")
    if args.warm_start != evaluator.settings.warm_start:
        evaluator = dataclasses.replace(evaluator, settings=dataclasses.replace(
            evaluator.settings, warm_start=args.warm_start))
    grid = grid_from_args(evaluator, args.boundary, args.step)
    if grid.size > MAX_POINTS:
        seconds_each, bytes_each = sweep_cost(evaluator, grid)
        check_work(args, f"--step {args.step:g}", grid.size, MAX_POINTS, "points",
                   grid.size * seconds_each / args.workers, grid.size * bytes_each)
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
    landscape = read_landscape(args.file)
    if args.output is not None:
        args.output.mkdir(parents=True, exist_ok=True)
    report(landscape, args.output)
    return 0
