"""``ergohandover score --input``: a Posture CSV scored with every score and the workload; or,
where the file names unseen columns (as ``score --keypoints`` writes them), scored as the
keypoints were: each score exact where nothing it depends on is unseen, else its interval."""

from __future__ import annotations

import argparse

import numpy as np
import pandas as pd

from ..ergonomics import SCORE_COLUMNS, ScoringSettings, score_postures
from ..ergonomics.posture import POSTURE_COLUMNS
from ..io.csv_input import InputError, numeric_columns
from ..io.posture_csv import UNSEEN_COLUMN, read_open_postures
from .options import body_from_args, lift_from_args, model_flags
from .parser import given

WORKLOAD_FLAGS = (*model_flags(), "lift_frequency", "lift_duration", "lift_destination", "rate",
                  "hold", "shift_hours")
"""The flags the workload columns read: only with ``--input`` whose every angle is given."""
INTERVAL_SCORES = ("reba", "rula", "paper_postural")
"""The scores a file with unseen columns gives, each with its ``_lo`` and ``_hi``."""


def input_scores(args: argparse.Namespace, settings: ScoringSettings,
                 plan) -> tuple[pd.DataFrame, str]:
    """The table of ``--input`` and what it holds."""
    name = "standard input" if args.input == "-" else args.input
    text, posture, unseen = read_open_postures(args.input, what=name, radians=args.radians,
                                               radians_flag="--radians")
    if unseen is not None:
        return open_scores(args, text, posture, unseen, settings, name)
    scores = pd.DataFrame(score_postures(posture, settings))
    work = input_workload(text, posture, args, plan)
    passthrough = text.drop(columns=[c for c in text.columns
                                     if c in SCORE_COLUMNS or c in work.columns])
    return pd.concat([passthrough, scores, work], axis=1), f"{len(text)} postures"


def open_scores(args: argparse.Namespace, text: pd.DataFrame, posture, unseen: np.ndarray,
                settings: ScoringSettings, name: str) -> tuple[pd.DataFrame, str]:
    """A file with an ``unseen`` column, scored as ``score --keypoints`` scores its frames (the
    same columns, so that its output read back gives the same scores and intervals): the
    file's columns, ``unseen`` rewritten to what is unseen now (a cell filled since is
    measured), and each score of :data:`INTERVAL_SCORES` with its ``_lo`` and ``_hi``."""
    from ..capture import Captured, capture_scores

    workload = [f for f in WORKLOAD_FLAGS if f in given(args)]
    if workload:
        raise InputError(f"--{workload[0].replace('_', '-')} cannot be used with {name}: it "
                         "has an 'unseen' column (a capture's), and the workload columns need "
                         "every angle")
    scores = capture_scores(Captured(dict(posture), unseen), settings)
    derived = {*SCORE_COLUMNS, *(f"{s}_{end}" for s in INTERVAL_SCORES
                                 for end in ("lo", "hi", "probabilities"))}
    table = text.drop(columns=[c for c in text.columns if c in derived])
    names = np.array(POSTURE_COLUMNS, dtype=object)
    table[UNSEEN_COLUMN] = [";".join(names[row]) for row in unseen]
    for score, values in scores.items():
        table[score] = pd.array(np.where(np.isfinite(values), values, np.nan), dtype="Int64")
    open_rows = int(unseen.any(axis=1).sum())
    shown = ", ".join(c for c, hidden in zip(POSTURE_COLUMNS, unseen.any(axis=0), strict=True)
                      if hidden)
    note = f" (unseen: {shown})" if shown else ""
    return table, (f"{len(text)} postures, {open_rows} with unseen columns{note}: scores "
                   "as intervals where those leave them open; no workload columns (they need "
                   "every angle)")


def input_workload(text: pd.DataFrame, posture, args: argparse.Namespace,
                   plan) -> pd.DataFrame:
    """OWAS, the back load of the body the flags describe, a shift of handovers (``plan``)
    at each posture and, where the file gives the box's location (``x, y, z``, worker frame),
    the lifting equation."""
    from ..workload import Levers, shift_table, workload_table

    table = pd.DataFrame({name: posture[name] for name in posture})
    located = [c for c in ("x", "y", "z") if c in text.columns]
    if located and len(located) < 3:
        missing = sorted({"x", "y", "z"} - set(located))
        raise InputError(f"{args.input}: has {', '.join(located)} but not {', '.join(missing)} "
                         "(the box's location needs all three, or none)")
    allowed = {"x": "a finite coordinate in metres", "y": "a height in metres >= 0",
               "z": "a finite coordinate in metres"}  # y: the hands' height, above the floor
    for c, values in numeric_columns(text, {c: allowed[c] for c in located}, args.input).items():
        bad = np.flatnonzero(~np.isfinite(values) | ((values < 0) if c == "y" else False))
        if bad.size:
            raise InputError(f"{args.input}: row {bad[0] + 1}, column '{c}': "
                             f"{text[c].iloc[bad[0]]} is not allowed (expected {allowed[c]})")
        table[c] = values
    body = body_from_args(args)
    return pd.concat([workload_table(table, Levers.of(body), lift_from_args(args)),
                      shift_table(table, body, plan)], axis=1)


