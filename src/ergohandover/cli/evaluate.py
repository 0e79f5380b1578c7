"""``ergohandover evaluate``: the twin's posture, feasibility and scores at given box locations."""

from __future__ import annotations

import argparse
import sys

import numpy as np
import pandas as pd
from tqdm import tqdm

from ..io.atomic import atomic_write_csv
from ..io.csv_input import InputError, numeric_columns, read_csv_text, require_columns
from ..scene.render import render_points
from ..sim import require_display
from ..twin.evaluate import (
    EVALUATION_COLUMNS,
    REASONS,
    Evaluator,
    evaluate,
    joint_angles,
    posture_solver,
)
from ..twin.stance import after_step
from .options import (
    add_evaluator_arguments,
    add_gui_argument,
    add_lift_arguments,
    add_shift_arguments,
    add_workers_argument,
    evaluator_from_args,
    lift_from_args,
    run_folder,
    shift_from_args,
    writable,
)
from .values import REACH_M, beyond_reach, output_file, output_folder

DESCRIPTION = f"""\
Evaluate box locations: for each row of --points (columns x, y, z: the box centre in the worker
frame, metres; x to the worker's right, y up, z forward) the twin grips both handles; its
posture, feasibility ({', '.join(REASONS)}) and every score are written to
--output (the Evaluation CSV, whose columns docs/architecture.md lists under "File contracts";
scores are empty where infeasible), then OWAS, the revised NIOSH lifting equation for a lift
from the box's location to --lift-destination, the static back load, and a shift of such
handovers (--rate, --hold, --shift-hours): each joint's load as a share of its strength, when it
first fails and what it keeps at the shift's end, and the low back's daily dose
(docs/workload.md)."""

LOCATION = "a finite coordinate in metres"
POINTS_HELP = "box locations: columns x, y, z [m], worker frame; - for stdin"


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "evaluate", help="posture and scores of the twin at box locations",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", required=True, metavar="CSV",
                        help=POINTS_HELP)
    parser.add_argument("--output", type=output_file, metavar="CSV",
                        help="Evaluation CSV to write (atomically; its folder is created if "
                        "needed), or - for standard output (default: "
                        "runs/evaluate/<timestamp>/evaluation.csv)")
    add_evaluator_arguments(parser)
    add_lift_arguments(parser)
    add_shift_arguments(parser)
    parser.add_argument("--render", metavar="DIR", type=output_folder,
                        help="also write one PNG per point into DIR (created if needed)")
    add_gui_argument(parser, "the first point: the worker in its solved posture holding the box "
                     "there, the robot holding it too")
    add_workers_argument(parser, "processes to use")
    parser.set_defaults(run=run)


def read_points(source: str) -> np.ndarray:
    """(N, 3) locations from a points CSV; a bad cell is a one-line InputError."""
    what = "standard input" if source == "-" else source
    frame = read_csv_text(source, what)
    require_columns(frame, ("x", "y", "z"), what)
    cols = numeric_columns(frame, dict.fromkeys(("x", "y", "z"), LOCATION), what)
    points = np.column_stack([cols["x"], cols["y"], cols["z"]])
    bad = np.argwhere(~np.isfinite(points))
    if bad.size:
        row, col = bad[0]
        raise InputError(f"{what}: row {row + 1}, column '{'xyz'[col]}': {points[row, col]:g} "
                         f"is not allowed (expected {LOCATION})")
    far = np.flatnonzero(np.abs(points).max(axis=1) > REACH_M)
    if far.size:
        row = int(far[0])
        raise InputError(f"{what}: row {row + 1}: {','.join(f'{v:g}' for v in points[row])} is "
                         f"{beyond_reach(points[row])} ({far.size} such rows)")
    return points


def show_in_window(evaluator: Evaluator, location: np.ndarray, q: np.ndarray, robot=None,
                   arms: dict[str, np.ndarray] | None = None, lift: float = 0.0) -> None:
    """PyBullet's own window showing the worker in posture ``q`` [rad] holding the box at
    ``location`` (worker frame [m]) and the robot holding it: with ``arms`` [rad] at ``lift``
    [m] (a carry's last pose), else its first hold there; ``robot`` is where the robot stands
    (default :class:`~ergohandover.scene.robot.RobotSpec`). Returns when the user closes the
    window or presses Ctrl-C."""
    from ..scene.scene_render import TARGET, VIEWS, SceneRenderer
    from ..scene.world import WorkerPosture, World

    posture = WorkerPosture(posture_solver(evaluator).model.joint_names, q)
    with SceneRenderer(World(evaluator.body, evaluator.task, robot, gui=True)) as scene:
        if arms is None:
            arms, lift = scene.world.hold_pose(location, posture)
        scene.pose(location, arms, posture, lift)
        scene.world.look_at(VIEWS["side"], TARGET)
        x, y, z = location
        print(f"showing the box at ({x:.3f}, {y:.3f}, {z:.3f}) m in PyBullet's window; close it "
              "or press Ctrl-C to finish", file=sys.stderr)
        scene.world.wait_until_closed()


def run(args: argparse.Namespace) -> int:
    if args.gui:  # before any work: without a display nothing is computed or written
        require_display("--gui")
    from ..workload import Levers, shift_table, workload_table

    evaluator = evaluator_from_args(args)
    lift = lift_from_args(args)
    plan = shift_from_args(args)
    points = read_points(args.points)
    with tqdm(total=len(points), unit="loc", desc="evaluate", file=sys.stderr,
              disable=len(points) < 2000) as bar:
        table = evaluate(points, evaluator, workers=args.workers, progress=bar.update,
                         joints=args.render is not None or args.gui)
    output = args.output or str(run_folder("evaluate") / "evaluation.csv")
    # OWAS, the lifting equation, the back load and the shift where the twin holds the box.
    taken = table["feasible"].to_numpy(dtype=bool)
    work = workload_table(table, Levers.of(evaluator.body), lift, rows=taken)
    work = pd.concat([work, shift_table(table, evaluator.body, plan, rows=taken)], axis=1)
    table = pd.concat([table, work], axis=1)
    # The Evaluation CSV, how far the feet stepped for a worker who may step, the workload.
    columns = [*EVALUATION_COLUMNS, *(["step_m"] if "step_m" in table else []), *work.columns]
    if output == "-":
        table[columns].to_csv(sys.stdout, index=False)
    else:
        atomic_write_csv(table[columns], writable(output))
    # A stepping worker is drawn where its feet went: the box relative to them.
    drawn = after_step(points, table["step_m"].to_numpy()) if "step_m" in table else points
    if args.render:
        render_points(table, drawn, evaluator, args.render)
    feasible = int(table["feasible"].sum())
    print(f"evaluated {len(table)} locations ({feasible} feasible)"
          + ("" if output == "-" else f" -> {output}"), file=sys.stderr)
    if args.gui:
        show_in_window(evaluator, drawn[0], joint_angles(table)[0])
    return 0
