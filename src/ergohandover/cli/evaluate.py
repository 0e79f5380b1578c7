"""``ergohandover evaluate``: the twin's posture, feasibility and scores at given box locations."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np
from tqdm import tqdm

from ..io.atomic import atomic_write_csv
from ..io.csv_input import InputError, numeric_columns, read_csv_text, require_columns
from ..twin.evaluate import SOLVERS, Evaluator, evaluate, posture_solver
from ..twin.task import TaskSpec
from .options import add_body_arguments, body_from_args

DESCRIPTION = """\
Evaluate box locations: for each row of --points (columns x, y, z: the box centre in the worker
frame, metres; x to the worker's right, y up, z forward) the twin grips both handles; its
posture, feasibility (hand_miss, box_collision, unbalanced) and every score are written to
--output (DESIGN.md's Evaluation CSV; scores are empty where infeasible)."""

LOCATION = "a finite coordinate in metres"


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "evaluate", help="posture and scores of the twin at box locations",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", required=True, metavar="CSV",
                        help="box locations: columns x, y, z [m], worker frame; - for stdin")
    parser.add_argument("--output", required=True, metavar="CSV",
                        help="Evaluation CSV to write (atomically), or - for standard output")
    add_body_arguments(parser)
    parser.add_argument("--solver", choices=SOLVERS, default="numpy",
                        help="numpy: whole-body solver (balance, gaze, palms); pybullet: "
                        "PyBullet's IK on the hands only (default: numpy)")
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
    if args.workers < 1:
        raise InputError(f"workers = {args.workers} is outside the valid range (at least 1)")
    body, task = body_from_args(args), TaskSpec()
    points = read_points(args.points)
    with tqdm(total=len(points), unit="loc", desc="evaluate", file=sys.stderr,
              disable=len(points) < 2000) as bar:
        table = evaluate(points, body, task, solver=args.solver, workers=args.workers,
                         progress=bar.update)
    if args.output == "-":
        table.to_csv(sys.stdout, index=False)
    else:
        atomic_write_csv(table, args.output)
    if args.render:
        render_points(table, points, Evaluator(body, task, args.solver), args.render)
    feasible = int(table["feasible"].sum())
    print(f"evaluated {len(table)} locations ({feasible} feasible)"
          + ("" if args.output == "-" else f" -> {args.output}"), file=sys.stderr)
    return 0


def render_points(table, points: np.ndarray, evaluator: Evaluator, folder: Path) -> None:
    """One PNG per point: the twin (same posture as the CSV: the solver is deterministic)."""
    from ..scene.render import Renderer, caption_lines, save_png

    folder.mkdir(parents=True, exist_ok=True)
    solver = posture_solver(evaluator)
    q = solver.solve(points).q
    renderer = Renderer(evaluator.body, evaluator.task)
    try:
        for i in tqdm(range(len(points)), desc="render", unit="png", file=sys.stderr,
                      disable=len(points) < 5):
            renderer.pose(solver.model.joint_names, q[i], points[i])
            save_png(renderer.views(), caption_lines(table.iloc[i]),
                     folder / f"point_{i + 1:04d}.png")
    finally:
        renderer.close()
