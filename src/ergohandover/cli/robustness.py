"""``ergohandover robustness``: scores under posture-measurement error, at box locations or for
given postures."""

from __future__ import annotations

import argparse
import shlex
import sys
import time

import numpy as np
import pandas as pd

from ..io.atomic import atomic_write_all
from ..io.csv_input import InputError, numeric_columns, read_csv_text, require_columns
from ..io.posture_csv import read_postures
from ..robustness.margins import margin_table
from ..robustness.measured_error import MEASURED_ERROR
from ..robustness.posture_error import (
    ANGLE_COLUMNS,
    CHUNK_POSTURES,
    SCORES,
    STRUCTURES,
    ErrorModel,
    monte_carlo,
)
from ..robustness.search import postures_at
from . import defaults
from .evaluate import LOCATION, POINTS_HELP
from .options import (
    add_evaluator_arguments,
    add_workers_argument,
    add_yes_argument,
    check_work,
    evaluator_from_args,
    model_flags_given,
    writable,
)
from .values import BadValue, choice, existing_file, number, output_file, whole

DESCRIPTION = f"""\
Score postures as a site would measure them: every measured angle ({len(ANGLE_COLUMNS)} columns of
the Posture CSV) carries zero-mean Gaussian error of SD --angle-sd degrees, independently or
shared by the left and right side of each paired angle (--structure bilateral); flags, load and
task factors are taken as known. Give --points (box locations x, y, z [m], worker frame: the
twin is evaluated there, as by 'ergohandover evaluate') or --postures (a Posture CSV, as read by
'ergohandover score'). One row per location, angle SD and score ({', '.join(SCORES)}): the
nominal score, the mean of --draws measured scores and its standard error, the share of draws
at or below the nominal score and the 5% and 95% quantiles. A location is named by the CSV's
name or location column, else row<i>; an infeasible location (--points) has feasible 0 and empty
statistics. Each SD draws from its own generator spawned from --seed. --measured-error scores
instead under an IMU system's error as it was measured against optical motion capture: a bias
and an SD per joint, correlated within a segment and between sides (Schall et al. 2016 for the
trunk and upper arm, the rest assumed; the report's robustness section lists them)."""
STATS = ("nominal", "mean", "mean_se", "p_nominal_or_better", "q05", "q95", "draws")
WHOLE = ("nominal", "q05", "q95", "draws")


def input_file(text: str) -> str:
    """A CSV file that exists, or ``-`` for standard input."""
    return text if text == "-" else str(existing_file(text))


def file_to_write(text: str) -> str:
    """A CSV file to write (standard output is the table's)."""
    if text == "-":
        raise BadValue(text, "standard output is the main table's: name a file")
    return output_file(text)


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "robustness", help="scores under posture-measurement error (Monte Carlo)",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", type=input_file, metavar="CSV",
                        help=POINTS_HELP)
    parser.add_argument("--postures", type=input_file, metavar="CSV",
                        help="a Posture CSV to read instead of --points; - for stdin")
    parser.add_argument("--angle-sd", type=number(0, MAX_ANGLE_SD_DEG, "deg"), nargs="+",
                        default=None, metavar="DEG",
                        help="the angle error's standard deviation [deg], >= 0; one or more "
                        f"values (default: {defaults.ANGLE_SD:g})")
    parser.add_argument("--measured-error", action="store_true",
                        help="score under an IMU-like error model per joint (bias, SD, "
                        "correlations; 4 of its 15 SDs measured, the rest assumed) instead of "
                        "--angle-sd; angle_sd_deg is then empty and structure names the model")
    parser.add_argument("--structure", type=choice(STRUCTURES), default=None,
                        metavar="|".join(STRUCTURES), help="independent errors, or one error "
                        f"for both sides of each paired angle (default: {STRUCTURES[0]})")
    parser.add_argument("--draws", type=whole(1), default=defaults.DRAWS, metavar="N",
                        help="measured copies of each posture, an integer >= 1 (default: "
                        f"{defaults.DRAWS})")
    parser.add_argument("--seed", type=whole(0), default=defaults.SEED, metavar="N",
                        help=f"seed of the errors, an integer >= 0 (default: {defaults.SEED})")
    parser.add_argument("--output", type=output_file, metavar="CSV",
                        help="table to write (atomically; its folder is created if needed), "
                        "or - for standard output (default: standard output)")
    parser.add_argument("--flips", type=file_to_write, metavar="CSV",
                        help="also write each item score's share of draws that differ from its "
                        "nominal: columns location, angle_sd_deg, item, p_flip")
    parser.add_argument("--margins", type=file_to_write, metavar="CSV",
                        help="also write each angle's margin [deg] to a change of each score: "
                        "columns location, angle, value, score, margin_deg")
    add_evaluator_arguments(parser)
    add_workers_argument(parser, "processes evaluating the twin at --points")
    add_yes_argument(parser, f"{MAX_MEASURED:,} measured postures")
    parser.set_defaults(run=run)


def names_of(frame: pd.DataFrame) -> list[str]:
    """Each row's name: its ``name`` (or ``location``) cell, else ``row<i>`` (1-based)."""
    column = next((c for c in ("name", "location") if c in frame.columns), None)
    cells = frame[column].str.strip() if column else pd.Series([""] * len(frame))
    return [cell or f"row{i + 1}" for i, cell in enumerate(cells)]


def points_from(frame: pd.DataFrame, what: str) -> np.ndarray:
    """(N, 3) locations from a points CSV's cells, checked as ``evaluate`` checks them."""
    require_columns(frame, ("x", "y", "z"), what)
    points = np.column_stack(list(numeric_columns(frame, dict.fromkeys("xyz", LOCATION),
                                                  what).values()))
    bad = np.argwhere(~np.isfinite(points))
    if bad.size:
        row, col = bad[0]
        raise InputError(f"{what}: row {row + 1}, column '{'xyz'[col]}': {points[row, col]:g} "
                         f"is not allowed (expected {LOCATION})")
    return points


MAX_ANGLE_SD_DEG = 45.0
"""The largest error SD taken: beyond it a measured angle says next to nothing of the true one
(video and IMU errors reported for posture assessment are a few to about 20 degrees)."""
MAX_MEASURED = 500_000_000
"""Measured postures (draws x postures x error models) a run scores without --yes (the
study's robustness part scores 4,000 a location)."""
MAX_MEMORY_BYTES = 4e9
"""Memory a run may take at once without --yes."""
ROW_BYTES = 50 * 8 + 64
"""A measured posture while it is scored: its ~50 float64 columns and the scores' arrays."""


def check_draws(args: argparse.Namespace, postures: int) -> None:
    """Refuse a run beyond :data:`MAX_MEASURED` measured postures, or one whose chunk of
    measured postures (at least one posture's draws) would not fit :data:`MAX_MEMORY_BYTES`,
    unless --yes, timing the Monte Carlo on a few postures first."""
    amount = args.draws * postures * len(error_models(args))
    # One chunk is scored at once; the three scores of every measured posture are kept.
    memory = max(args.draws, CHUNK_POSTURES) * ROW_BYTES + amount * 3
    if amount <= MAX_MEASURED and memory <= MAX_MEMORY_BYTES:
        return
    from ..ergonomics import Posture

    sample = Posture.random(64, np.random.default_rng(0))
    start = time.perf_counter()
    monte_carlo(sample, ErrorModel(5.0), 2000, np.random.default_rng(0))
    seconds_each = (time.perf_counter() - start) / (64 * 2000)  # one core: not spread
    check_work(args, f"--draws {args.draws}", amount, MAX_MEASURED, "measured postures",
               amount * seconds_each, memory, memory > MAX_MEMORY_BYTES)


def read_input(args: argparse.Namespace):
    """(locations: location[, x, y, z, feasible], the feasible ones' postures, feasible mask)."""
    if (args.points is None) == (args.postures is None):
        raise InputError("give exactly one of --points CSV or --postures CSV (got "
                         f"{'neither' if args.points is None else 'both'})")
    flag, source = ("--points", args.points) if args.postures is None else (
        "--postures", args.postures)
    what = "standard input" if source == "-" else f"{flag} {shlex.quote(source)}"
    if args.postures is not None:
        if model_flags_given(args):
            raise InputError(f"{model_flags_given(args)[0]} cannot be used with --postures "
                             "(the worker and task flags describe the twin at --points)")
        frame, posture = read_postures(source, what)
        check_draws(args, posture.n)
        return pd.DataFrame({"location": names_of(frame)}), posture, np.ones(posture.n, bool)
    evaluator = evaluator_from_args(args)
    frame = read_csv_text(source, what)
    points = points_from(frame, what)
    check_draws(args, len(points))  # before the twin solves a point
    posture, feasible = postures_at(points, evaluator, args.workers)
    locations = pd.DataFrame({"location": names_of(frame),
                              **dict(zip("xyz", points.T, strict=True)),
                              "feasible": feasible.astype(int)})
    return locations, posture.take(np.flatnonzero(feasible)), feasible


def ordered(parts: list[pd.DataFrame], locations: pd.DataFrame) -> pd.DataFrame:
    """Rows of every part (each with a ``row`` column: the location's index), location-major
    (the parts' order kept within a location), the location's columns first."""
    frame = pd.concat(parts, ignore_index=True).sort_values("row", kind="stable")
    where = locations.iloc[frame["row"].to_numpy()].reset_index(drop=True)
    return pd.concat([where, frame.drop(columns="row").reset_index(drop=True)], axis=1)


def error_models(args: argparse.Namespace) -> list[tuple[float, str, object]]:
    """(angle SD or NaN, structure or the model's name, model) for each error model asked
    for; --measured-error takes neither --angle-sd nor --structure."""
    if args.measured_error:
        given = [f for f, v in (("--angle-sd", args.angle_sd), ("--structure", args.structure))
                 if v is not None]
        if given:
            raise InputError(f"{given[0]} cannot be used with --measured-error (the measured "
                             "model sets every angle's error and how they correlate)")
        return [(np.nan, MEASURED_ERROR.name, MEASURED_ERROR)]
    structure = args.structure or STRUCTURES[0]
    return [(sd, structure, ErrorModel(sd, structure))
            for sd in args.angle_sd or [defaults.ANGLE_SD]]


def run(args: argparse.Namespace) -> int:
    models = error_models(args)
    locations, posture, feasible = read_input(args)
    rows = np.flatnonzero(feasible)
    names = locations["location"].to_numpy()
    spawned = np.random.SeedSequence(args.seed).spawn(len(models))
    every = pd.DataFrame({"row": np.repeat(np.arange(len(locations)), len(SCORES)),
                          "score": np.tile(SCORES, len(locations))})
    tables, flips = [], [pd.DataFrame(columns=["row", "angle_sd_deg", "item", "p_flip"])]
    for (sd, structure, model), sequence in zip(models, spawned, strict=True):
        found = pd.DataFrame(columns=["row", "score", *STATS])
        if rows.size:
            result = monte_carlo(posture, model, args.draws, np.random.default_rng(sequence))
            found = result.table(rows).rename(columns={"location": "row"})
            flips += [pd.DataFrame({"row": rows, "angle_sd_deg": sd, "item": item,
                                    "p_flip": share}) for item, share in result.flips.items()]
        table = every.merge(found, on=["row", "score"], how="left")
        table.insert(1, "angle_sd_deg", sd)
        table.insert(2, "structure", structure)
        tables.append(table)
    table = ordered(tables, locations)
    table[list(WHOLE)] = table[list(WHOLE)].astype(float).astype("Int64")
    outputs = {args.output: table}
    if args.flips:
        outputs[args.flips] = ordered(flips, locations[["location"]])
    if args.margins:
        outputs[args.margins] = (margin_table(posture, names[rows]) if rows.size else
                                 pd.DataFrame(columns=["location", "angle", "value", "score",
                                                       "margin_deg"]))
    # Everything computed: now written, all or none.
    atomic_write_all({writable(path): (lambda h, f=frame: f.to_csv(h, index=False))
                      for path, frame in outputs.items() if path not in (None, "-")})
    if args.output in (None, "-"):
        table.to_csv(sys.stdout, index=False)
        return 0
    paper = table[table["score"] == "paper_postural"]
    for row in paper.itertuples(index=False):
        error = (row.structure if pd.isna(row.angle_sd_deg) else
                 f"angle SD {row.angle_sd_deg:g} deg")
        head = f"{row.location} ({error}): "
        print(head + ("infeasible" if pd.isna(row.nominal) else
                      f"paper_postural {row.nominal} -> mean {row.mean:.2f}, "
                      f"P(<= {row.nominal}) {row.p_nominal_or_better:.3f}"), file=sys.stderr)
    errors = "the measured error" if args.measured_error else f"{len(models)} angle SDs"
    print(f"{len(locations)} locations x {errors}, {args.draws} draws each -> {args.output}",
          file=sys.stderr)
    return 0
