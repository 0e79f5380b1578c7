"""What the commands share: options generated from frozen dataclass configs, the worker's
body flags, X,Y,Z values that start with a minus, and the default output folder.

A field's ``metadata["help"]`` becomes its ``--help`` text and ``metadata["choices"]`` its
choices; the dataclass's own validation runs when the config is built from the parsed flags.
"""

from __future__ import annotations

import argparse
import dataclasses
import re
import time
from pathlib import Path
from typing import Any, TypeVar

T = TypeVar("T")


def flag_name(field: dataclasses.Field) -> str:
    return "--" + field.name.replace("_", "-")


def add_dataclass_arguments(parser: argparse.ArgumentParser | Any, cls: type,
                            title: str | None = None) -> None:
    """Add one ``--flag`` per field of dataclass ``cls`` (default: the field's default)."""
    group = parser.add_argument_group(title) if title else parser
    for field in dataclasses.fields(cls):
        meta = field.metadata
        kind = type(field.default)
        group.add_argument(
            flag_name(field),
            dest=field.name,
            type=kind if kind in (int, float, str) else str,
            default=None,
            choices=meta.get("choices"),
            metavar=None if "choices" in meta else field.name.split("_")[-1].upper(),
            help=f"{meta.get('help', '')} (default: {field.default})",
        )


def dataclass_from_args(cls: type[T], args: argparse.Namespace) -> T:
    """Build ``cls`` from the flags given on the command line; unset flags keep defaults."""
    given = {
        f.name: getattr(args, f.name)
        for f in dataclasses.fields(cls)
        if getattr(args, f.name, None) is not None
    }
    return cls(**given)


def add_body_arguments(parser: argparse.ArgumentParser) -> None:
    """``--percentile``, ``--stature``, ``--mass``, ``--sex``: the worker's size."""
    from ..twin.anthropometry import PERCENTILES

    group = parser.add_argument_group("worker (default: ANSUR II 50th-percentile man)")
    group.add_argument("--percentile", choices=sorted(PERCENTILES),
                       help="a named survey percentile (stature, mass and sex together)")
    group.add_argument("--stature", type=float, metavar="M", help="stature [m], 1.40-2.10")
    group.add_argument("--mass", type=float, metavar="KG", help="body mass [kg], 35-160")
    group.add_argument("--sex", choices=("male", "female"), help="sex")


def body_from_args(args: argparse.Namespace):
    """The BodySpec the flags describe: a percentile, then any explicit overrides."""
    import dataclasses

    from ..twin.anthropometry import BodySpec

    body = BodySpec.from_percentile(args.percentile) if args.percentile else BodySpec()
    overrides = {k: v for k, v in (("stature_m", args.stature), ("mass_kg", args.mass),
                                   ("sex", args.sex)) if v is not None}
    return dataclasses.replace(body, **overrides) if overrides else body


def add_task_arguments(parser: argparse.ArgumentParser) -> None:
    """One flag per :class:`~ergohandover.twin.task.TaskSpec` field: the box and ``--gaze``."""
    from ..twin.task import TaskSpec

    add_dataclass_arguments(parser, TaskSpec, "task (default: the 6 kg box, gaze on)")


def task_from_args(args: argparse.Namespace):
    """The TaskSpec the task flags describe (defaults for those not given)."""
    from ..twin.task import TaskSpec

    return dataclass_from_args(TaskSpec, args)


def task_flags_given(args: argparse.Namespace) -> list[str]:
    """The task flags given on the command line, as typed (``--gaze``, ...)."""
    from ..twin.task import TaskSpec

    return [flag_name(f) for f in dataclasses.fields(TaskSpec)
            if getattr(args, f.name, None) is not None]


def add_evaluator_arguments(parser: argparse.ArgumentParser, solver: bool = True) -> None:
    """The worker, the task, the trunk-angle reference and (``solver``) the posture solver:
    everything an :class:`~ergohandover.twin.evaluate.Evaluator` is built from."""
    from ..twin.evaluate import SOLVERS, TRUNK_REFERENCES

    add_body_arguments(parser)
    add_task_arguments(parser)
    group = parser.add_argument_group("model")
    if solver:
        group.add_argument("--solver", choices=(*SOLVERS, "numpy"), default="whole-body",
                           help="whole-body: the twin's own solver (balance, gaze, palms; "
                           "compiled); pybullet: PyBullet's IK on the hands only; numpy is the "
                           "former name of whole-body (default: whole-body)")
    group.add_argument("--trunk-reference", choices=TRUNK_REFERENCES, default="vertical",
                       help="trunk flexion and side bend from vertical (the worksheets') or "
                       "relative to the pelvis (default: vertical)")


def evaluator_from_args(args: argparse.Namespace):
    """The Evaluator the flags describe (see :func:`add_evaluator_arguments`)."""
    import sys

    from ..twin.evaluate import Evaluator

    solver = getattr(args, "solver", "whole-body")
    if solver == "numpy":
        print("note: --solver numpy is the former name of --solver whole-body", file=sys.stderr)
    return Evaluator(body_from_args(args), task_from_args(args), solver,
                     trunk_reference=args.trunk_reference)


RUNS = Path("runs")
"""Where commands write by default (ignored by git): ``runs/<command>/<timestamp>/``. The study's
``results/`` and ``paper_figs/`` are written only by the study scripts."""


def run_folder(command: str) -> Path:
    """A new ``runs/<command>/<YYYYmmdd-HHMMSS>[-N]/`` below the working directory (created)."""
    stamp = time.strftime("%Y%m%d-%H%M%S")
    for n in range(1, 1000):
        folder = RUNS / command / (stamp if n == 1 else f"{stamp}-{n}")
        try:
            folder.mkdir(parents=True)
            return folder
        except FileExistsError:
            continue
    raise FileExistsError(f"{RUNS / command}: no free folder name for {stamp}")


COORDINATE_FLAGS = ("--start", "--boundary")
"""Flags whose value is a list of numbers, which may start with a minus sign."""
_NUMBERS = re.compile(r"^-\d*\.?\d+(e[-+]?\d+)?(,[-+]?\d*\.?\d+(e[-+]?\d+)?)*$", re.IGNORECASE)


def join_negative_values(argv: list[str]) -> list[str]:
    """``--start -0.3,0.8,0.9`` -> ``--start=-0.3,0.8,0.9``: argparse would take the value for
    an option because it starts with a minus; every X,Y,Z flag accepts it as typed."""
    out, i = [], 0
    while i < len(argv):
        if argv[i] in COORDINATE_FLAGS and i + 1 < len(argv) and _NUMBERS.match(argv[i + 1]):
            out.append(f"{argv[i]}={argv[i + 1]}")
            i += 2
        else:
            out.append(argv[i])
            i += 1
    return out
