"""``ergohandover evaluate``: the twin's posture, feasibility and scores at given box locations."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np
from tqdm import tqdm

from ..executor import check_workers
from ..io.atomic import atomic_write_csv
from ..io.csv_input import InputError, numeric_columns, read_csv_text, require_columns
from ..scene.render import render_points
from ..twin.evaluate import EVALUATION_COLUMNS, evaluate
from .options import add_evaluator_arguments, evaluator_from_args, run_folder

DESCRIPTION = """\
Evaluate box locations: for each row of --points (columns x, y, z: the box centre in the worker
frame, metres; x to the worker's right, y up, z forward) the twin grips both handles; its
posture, feasibility (hand_miss, box_collision, unbalanced) and every score are written to
--output (the Evaluation CSV, whose columns docs/architecture.md lists; scores are empty where
infeasible)."""

LOCATION = "a finite coordinate in metres"


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "evaluate", help="posture and scores of the twin at box locations",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", required=True, metavar="CSV",
                        help="box locations: columns x, y, z [m], worker frame; - for stdin")
    parser.add_argument("--output", metavar="CSV",
                        help="Evaluation CSV to write (atomically), or - for standard output "
                        "(default: runs/evaluate/<timestamp>/evaluation.csv)")
    add_evaluator_arguments(parser)
    parser.add_argument("--render", metavar="DIR", type=Path,
                        help="also write one PNG per point into DIR (created if needed)")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="processes to use (default: all cores)")
    parser.set_defaults(run=run)


def read_points(source: str) -> np.ndarray:
    """(N, 3) locations from a points CSV; a bad cell is a one-line InputError."""
    what = "standard input" if source == "-" else source
    frame = read_csv_text(source, what)
    require_columns(frame, ("x", "y", "z"), what)
    cols = numeric_columns(frame, dict.fromkeys(("x", "y", "z"), LOCATION))
    points = np.column_stack([cols["x"], cols["y"], cols["z"]])
    bad = np.argwhere(~np.isfinite(points))
    if bad.size:
        row, col = bad[0]
        raise InputError(f"row {row + 1}, column '{'xyz'[col]}': {points[row, col]:g} is not "
                         f"allowed (expected {LOCATION})")
    return points


def run(args: argparse.Namespace) -> int:
    check_workers(args.workers)
    evaluator = evaluator_from_args(args)
    points = read_points(args.points)
    with tqdm(total=len(points), unit="loc", desc="evaluate", file=sys.stderr,
              disable=len(points) < 2000) as bar:
        table = evaluate(points, evaluator, workers=args.workers, progress=bar.update,
                         joints=args.render is not None)
    output = args.output or str(run_folder("evaluate") / "evaluation.csv")
    if output == "-":
        table[list(EVALUATION_COLUMNS)].to_csv(sys.stdout, index=False)
    else:
        atomic_write_csv(table[list(EVALUATION_COLUMNS)], output)
    if args.render:
        render_points(table, points, evaluator, args.render)
    feasible = int(table["feasible"].sum())
    print(f"evaluated {len(table)} locations ({feasible} feasible)"
          + ("" if output == "-" else f" -> {output}"), file=sys.stderr)
    return 0
