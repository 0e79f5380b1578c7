"""``ergohandover score``: score postures with REBA, RULA and the paper's score, given as angles,
as captured 3D keypoints, or as a rater's worksheet items."""

from __future__ import annotations

import argparse
import sys
import textwrap
from typing import NamedTuple

import numpy as np
import pandas as pd

from ..ergonomics import ScoringSettings
from ..ergonomics.posture import COLUMN_BY_NAME, COLUMNS, REQUIRED_COLUMNS
from ..io.atomic import atomic_write_csv
from ..io.csv_input import InputError
from . import defaults
from .keypoints import BODY_FLAGS, MAX_FRAMES, score_keypoints
from .options import (
    add_body_arguments,
    add_dataclass_arguments,
    add_lift_arguments,
    add_shift_arguments,
    add_yes_argument,
    dataclass_from_args,
    run_folder,
    shift_from_args,
    writable,
)
from .parser import given
from .score_input import WORKLOAD_FLAGS, input_scores
from .values import BadValue, choice, existing_file, number, output_file, whole

KEYPOINT_FORMATS = ("h36m17", "coco17", "mediapipe33", "zed34", "smpl24", "bvh")
"""What ``--format`` takes (``ergohandover.capture.FORMATS`` and BVH files)."""
KEYPOINT_FLAGS = ("format", "up", "units", "frames", "missing", "unseen", "draws", "seed",
                  "assume", "load_kg", "joint_map", "yes", "neutral_frame")
"""The flags that only ``--keypoints`` reads."""


def optional_columns() -> str:
    """The optional Posture columns grouped by the value they take when absent."""
    by_default: dict[str, list[str]] = {}
    for column in COLUMNS:
        if column.default is not None:
            by_default.setdefault(f"{column.default:g}", []).append(column.name)
        elif column.same_as is not None:
            by_default.setdefault(f"as {column.same_as}", []).append(column.name)
    return "; ".join(f"{', '.join(names)} {value}" for value, names in by_default.items())


DESCRIPTION = f"""\
Score postures with REBA (Hignett & McAtamney 2000), RULA (McAtamney & Corlett 1993) and the
paper's additive postural score, given one of three ways:

  --input      a Posture CSV: one posture per row, angles in degrees, flexion + (its columns:
               docs/architecture.md, "File contracts"); writes its columns and every score
               (a --keypoints output: its scores and intervals again, from its unseen cells).
  --keypoints  3D keypoints of a pose estimator or motion capture (--format; CSV wide or long,
               NPY/NPZ, MediaPipe JSON, BVH): writes per frame the Posture columns measured
               from them (empty where the format cannot see a column), the unseen columns, and
               REBA, RULA and the paper's score, each exact where nothing it depends on is
               unseen, else the interval over the unseen columns' plausible ranges (with
               --unseen prior also its distribution). docs/capture.md.
  --items      a rater's worksheet: REBA's and/or RULA's item scores per row; writes Tables
               A/B/C and the final scores beside the file's columns, and says which rows'
               own scores disagree with the tables. docs/report.md, "A rater's worksheet".
{textwrap.fill(f"Optional Posture columns default: {optional_columns()}.", 96)}"""


def assumption(text: str) -> tuple[str, float]:
    """``COLUMN=VALUE``: a Posture column and a value within its rule."""
    from ..ergonomics import Posture, PostureError

    name, sep, value = text.partition("=")
    if not sep or name not in COLUMN_BY_NAME:
        import difflib

        close = difflib.get_close_matches(name, list(COLUMN_BY_NAME), n=3) if sep else []
        hint = f"; did you mean {' or '.join(close)}?" if close else ""
        raise BadValue(text, "expected COLUMN=VALUE with a Posture column (docs/architecture.md, "
                       f"\"File contracts\"){hint}")
    try:
        number_value = float(value)
    except ValueError:
        number_value = float("nan")
    try:
        Posture({**{c: np.zeros(1) for c in REQUIRED_COLUMNS}, name: np.array([number_value])})
    except PostureError:
        raise BadValue(text, f"{value!r} is not allowed for {name} (expected "
                       f"{COLUMN_BY_NAME[name].allowed})") from None
    return name, number_value


def length_unit(text: str) -> str:
    """``m``, ``cm``, ``mm`` or a positive number: the metres one unit of the file is."""
    from ..capture.readers import KeypointFileError, unit_scale

    try:
        unit_scale(text, text)
    except KeypointFileError:
        raise BadValue(text, "not a unit (expected m, cm, mm, or the metres one unit of the "
                       "file is, a number above 0)") from None
    return text


class JointMap(NamedTuple):
    """``--joint-map`` as typed and the landmark -> joint map it gives."""

    text: str
    landmarks: dict[str, str]


def joint_map(text: str) -> JointMap:
    """``NAME=JOINT,...`` or a file of such entries (commas or new lines; ``#`` comments): a
    landmark of the project (``left_hip``, ``spine``, ...) for each joint named."""
    from pathlib import Path

    from ..capture.rigs import parse_joint_map

    path = Path(text)
    if "=" not in text and not path.is_file():
        raise BadValue(text, "no such file, and not LANDMARK=JOINT,... (e.g. "
                       "left_hip=LThigh,right_hip=RThigh)")
    try:
        source = path.read_text(encoding="utf-8") if "=" not in text else text
    except (OSError, UnicodeDecodeError) as exc:
        raise BadValue(text, f"cannot be read ({exc.__class__.__name__})") from None
    try:
        return JointMap(text, parse_joint_map(source))
    except ValueError as exc:
        raise BadValue(text, str(exc)) from None


def frame_range(text: str) -> tuple[int, int]:
    """``A:B`` (frames A to B, 1-based, inclusive; either may be left out) or ``N``."""
    first, sep, last = text.partition(":")
    try:
        lo = int(first) if first else 1
        hi = (int(last) if last else sys.maxsize) if sep else lo
    except ValueError:
        raise BadValue(text, "expected A:B, A:, :B or N (frame numbers, 1-based)") from None
    if lo < 1 or hi < lo:
        raise BadValue(text, "expected frame numbers >= 1 with A <= B")
    return lo, hi


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "score", help="score postures (angles, captured keypoints or worksheet items) with "
        "REBA, RULA and the paper's score",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    inputs = parser.add_mutually_exclusive_group(required=True)
    inputs.add_argument("--input", metavar="CSV",
                        help="Posture CSV to read, or - for standard input")
    inputs.add_argument("--keypoints", type=existing_file, metavar="FILE",
                        help="keypoints to read (.csv, .npy, .npz, .json, .bvh), with --format")
    inputs.add_argument("--items", metavar="CSV",
                        help="worksheet item scores to read (REBA's and/or RULA's), or -")
    parser.add_argument("--output", type=output_file, metavar="CSV",
                        help="scores CSV to write (atomically; its folder is created if "
                        "needed), or - for standard output (default: "
                        "runs/score/<timestamp>/scores.csv)")
    capture = parser.add_argument_group("keypoints (with --keypoints)")
    capture.add_argument("--format", type=choice(KEYPOINT_FORMATS),
                         metavar="|".join(KEYPOINT_FORMATS),
                         help="the keypoints' format (docs/capture.md lists each one's joints "
                         "and what it measures)")
    capture.add_argument("--up", type=choice(("x", "-x", "y", "-y", "z", "-z")), metavar="AXIS",
                         help="the axis that points up in the file (default: the format's: "
                         "-y for h36m17, coco17, mediapipe33; z for zed34; y for smpl24, bvh)")
    capture.add_argument("--units", type=length_unit, metavar="m|cm|mm|METRES",
                         help="the keypoints' unit: m, cm, mm, or the metres one unit of the "
                         "file is (e.g. 0.0254 for inches; default: told from the length of "
                         "the legs, among m, cm, mm, inch and CMU's 1/0.45 inch)")
    capture.add_argument("--frames", type=frame_range, metavar="A:B",
                         help="score frames A to B only (1-based, inclusive; A:, :B or N)")
    capture.add_argument("--neutral-frame", type=whole(1, None), metavar="N",
                         help="a frame of the file (its number, 1-based) in which the person "
                         "stands relaxed: each shoulder's raise is measured from its clavicle "
                         "there (default: a BVH rig's rest pose, else the body model's for "
                         "the worker flags, else the 50th-percentile man's)")
    capture.add_argument("--joint-map", type=joint_map, metavar="FILE|NAME=JOINT,...",
                         help="with --format bvh: which of the file's joints is each landmark "
                         "(left_hip=LThigh,spine=Spine2,...; the landmarks: docs/capture.md), "
                         "for a rig whose names are not recognised, or to override it")
    capture.add_argument("--missing", type=choice(("error", "unseen")), default="error",
                         metavar="error|unseen", help="a frame with a missing (NaN, invisible) "
                         "point: refuse the file (default), or score the frame with the "
                         "columns that point decides as unseen")
    capture.add_argument("--unseen", type=choice(("interval", "prior")), default="interval",
                         metavar="interval|prior", help="what an unseen column gives: the "
                         "interval of each score over its plausible range (default), and with "
                         "'prior' also each score's distribution with unseen angles uniform "
                         "over their ranges")
    capture.add_argument("--draws", type=whole(1, 100_000), default=400, metavar="N",
                         help="with --unseen prior: values drawn per frame (default: 400)")
    capture.add_argument("--seed", type=whole(0, None), default=defaults.SEED, metavar="N",
                         help="with --unseen prior: the seed of the draws (default: "
                         f"{defaults.SEED})")
    capture.add_argument("--assume", type=assumption, action="append", metavar="COLUMN=VALUE",
                         help="a Posture column's value for every frame, known from elsewhere "
                         "(a task factor, or an angle the format cannot see); repeatable")
    add_yes_argument(capture, f"{MAX_FRAMES:,} frames")
    capture.add_argument("--load-kg", type=number(0, 25, "kg"), metavar="KG",
                         help="the load handled (default: 0 kg), as --assume load_kg=KG")
    parser.add_argument("--radians", action="store_true",
                        help="with --input, the file's angles are radians; with --format bvh, "
                        "its rotations are (converted to degrees; without it a file whose every "
                        "angle is within ±3.19 is refused as radians)")
    add_dataclass_arguments(parser, ScoringSettings, "scoring settings (what REBA/RULA leave "
                            "open)")
    # With --input: the body whose segments the back load weighs, and the lift.
    add_body_arguments(parser)
    add_lift_arguments(parser)
    add_shift_arguments(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    flags = given(args)
    if args.keypoints is None:
        stray = [f for f in KEYPOINT_FLAGS if f in flags]
        if stray:
            raise InputError(f"--{stray[0].replace('_', '-')} cannot be used with "
                             f"--{'input' if args.input else 'items'} (only with --keypoints)")
    elif args.format is None:
        raise InputError("--keypoints needs --format (h36m17, coco17, mediapipe33, zed34, "
                         "smpl24 or bvh)")
    if args.radians and not (args.input or args.format == "bvh"):
        raise InputError(f"--radians cannot be used with "
                         f"--{'keypoints' if args.keypoints else 'items'} (only with --input, "
                         "a Posture CSV's angles, or --format bvh, a BVH file's rotations)")
    if args.input is None:
        workload = [f for f in WORKLOAD_FLAGS if f in flags
                    and (args.keypoints is None or f not in BODY_FLAGS)]
        if workload:
            raise InputError(f"--{workload[0].replace('_', '-')} cannot be used with "
                             f"--{'keypoints' if args.keypoints else 'items'} (only with "
                             "--input: the workload columns need every angle)")
    settings = dataclass_from_args(ScoringSettings, args)
    plan = shift_from_args(args)
    if args.keypoints is not None:
        result = score_keypoints(args, settings)
        if result is None:  # read, scored and written a part at a time
            return 0
        table, what = result
    elif args.items is not None:
        table, what = item_scores(args.items)
    else:
        table, what = input_scores(args, settings, plan)
    # Only now, everything read and scored: a bad input leaves no folder behind.
    output = args.output or str(run_folder("score") / "scores.csv")
    if output == "-":
        table.to_csv(sys.stdout, index=False)
    else:
        atomic_write_csv(table, writable(output))
        print(f"scored {what} -> {output}", file=sys.stderr)
    return 0




def item_scores(source: str) -> tuple[pd.DataFrame, str]:
    """The table of ``--items`` and what it holds: the tables' scores beside the file's own;
    where the file gives a score the tables also give, the two are compared."""
    from ..ergonomics import PostureError
    from ..ergonomics.worksheet import item_columns, score_items, sheets_given
    from ..io.csv_input import numeric_columns, read_csv_text

    what = "standard input" if source == "-" else source
    text = read_csv_text(source, what)
    names = [c for s in sheets_given(text.columns) for c in item_columns(s) if c in text]
    numbers = numeric_columns(text, {c: "an item score" for c in names}, what)
    try:
        scored = score_items(numbers)
    except PostureError as exc:
        raise PostureError(f"{what}: {exc}", exc.row, exc.column, exc.value) from None
    table = text.copy()
    differs = [[] for _ in range(len(text))]
    items = {c for s in sheets_given(text.columns) for c in item_columns(s)}
    for name, values in scored.items():
        if name in items:
            continue
        if name in text.columns:  # the rater's own: kept, compared where given, ours beside it
            theirs = given_scores(text, name, what)
            for row in np.flatnonzero(~np.isnan(theirs) & (theirs != values)):
                differs[row].append(name)
            table = table.rename(columns={name: f"given_{name}"})
        table[name] = values
    table["differs"] = [";".join(d) for d in differs]
    bad = [i + 1 for i, d in enumerate(differs) if d]
    shown = ", ".join(map(str, bad[:10])) + (", …" if len(bad) > 10 else "")
    note = f"; the file's own scores differ from the tables in rows {shown}" if bad else ""
    return table, (f"{len(text)} worksheets of {what} ({', '.join(sheets_given(text.columns))})"
                   f"{note}")


def given_scores(text: pd.DataFrame, name: str, what: str) -> np.ndarray:
    """A score column the sheet gives, as numbers; NaN where its cell is empty (not given)."""
    cells = text[name].str.strip()
    values = pd.to_numeric(cells, errors="coerce").to_numpy(dtype=np.float64)
    bad = np.flatnonzero(np.isnan(values) & (cells != "").to_numpy())
    if bad.size:
        raise InputError(f"{what}: row {bad[0] + 1}, column '{name}': {cells.iloc[bad[0]]!r} "
                         "is not a number (expected the sheet's score, or an empty cell)")
    return values
