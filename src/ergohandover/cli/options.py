"""What the commands share: flags generated from frozen dataclass configs, the worker, task and
model flags, the grid flags, X,Y,Z values that start with a minus, and the output folders.

A field's ``metadata["help"]`` becomes its ``--help`` text, its range or choices the flag's
checker (:mod:`.values`), so a bad value is refused while parsing, naming the flag. Every shared
flag's default is :mod:`.defaults`', the study's.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import re
import sys
import time
from pathlib import Path
from typing import Any, TypeVar

from ..io.csv_input import InputError
from . import defaults
from .measurements import FLAGS, add_measurement_arguments, measured_body
from .parser import given
from .refusals import BODY_FLAGS, model, read_landscape
from .values import (
    boundary,
    choice,
    existing_file,
    field_value,
    number,
    output_folder,
    rule,
    unit_of,
    whole,
)

T = TypeVar("T")


def flag_name(field: dataclasses.Field) -> str:
    return "--" + field.name.replace("_", "-")


def add_dataclass_arguments(parser: argparse.ArgumentParser | Any, cls: type,
                            title: str | None = None,
                            overrides: dict[str, Any] | None = None) -> None:
    """Add one ``--flag`` per field of dataclass ``cls``; its default is the field's, or the
    shared one in ``overrides`` (field name -> default)."""
    group = parser.add_argument_group(title) if title else parser
    for field in dataclasses.fields(cls):
        default = (overrides or {}).get(field.name, field.default)
        choices = field.metadata.get("choices")
        group.add_argument(
            flag_name(field), dest=field.name, type=field_value(field), default=default,
            metavar="|".join(choices) if choices else field.name.split("_")[-1].upper(),
            help=field_help(field, default))


def field_help(field: dataclasses.Field, default: Any) -> str:
    """A ranged field's help text, its range (once: some texts state it already) and default."""
    meta, text = field.metadata, field.metadata.get("help", "")
    if not meta.get("choices") and f"{meta['lo']:g}-{meta['hi']:g}" not in text:
        text += f", {rule(meta['lo'], meta['hi'], unit_of(field))}"
    return f"{text} (default: {default})"


def dataclass_from_args(cls: type[T], args: argparse.Namespace) -> T:
    """Build ``cls`` from its flags (each already checked against the field's range)."""
    return model(cls, **{f.name: getattr(args, f.name) for f in dataclasses.fields(cls)})


def add_body_arguments(parser: argparse.ArgumentParser) -> None:
    """``--percentile``, ``--stature``, ``--mass``, ``--sex``: the worker's size."""
    from ..twin.anthropometry import MASS_RANGE_KG, PERCENTILES, SEXES, STATURE_RANGE_M
    from ..workload.manikins import MANIKINS

    names = sorted(PERCENTILES)
    group = parser.add_argument_group(f"worker (default: --percentile {defaults.PERCENTILE})")
    group.add_argument("--percentile", type=choice(names), default=defaults.PERCENTILE,
                       metavar="|".join(names), help="a named ANSUR II percentile: stature, "
                       f"mass and sex together (default: {defaults.PERCENTILE})")
    group.add_argument("--manikin", type=choice(tuple(MANIKINS)), metavar="|".join(MANIKINS),
                       help="a standard boundary manikin instead of --percentile: the 5th-"
                       "percentile woman (f05), the 50th woman, the 50th man, the 95th man")
    group.add_argument("--stature", type=number(*STATURE_RANGE_M, "m"), metavar="M",
                       help=f"stature [m], {rule(*STATURE_RANGE_M)} (default: the "
                       "percentile's)")
    group.add_argument("--mass", type=number(*MASS_RANGE_KG, "kg"), metavar="KG",
                       help=f"body mass [kg], {rule(*MASS_RANGE_KG)} (default: the "
                       "percentile's)")
    group.add_argument("--sex", type=choice(SEXES), metavar="|".join(SEXES),
                       help="sex (default: the percentile's)")
    add_measurement_arguments(group)


def body_from_args(args: argparse.Namespace):
    """The BodySpec the flags describe (described in ``args.worker_line``).

    A named ``--percentile`` or ``--manikin`` with any explicit overrides, then the worker's
    own measurements; without one, a body given by stature, mass, sex or measurements is the
    body model's for what is given (:func:`.measurements.measured_body`); with nothing given,
    the default worker.
    """
    from ..twin.anthropometry import BodySpec
    from ..workload.manikins import MANIKINS

    flags = given(args)
    if args.manikin is not None and "percentile" in flags:
        raise InputError(f"--manikin {args.manikin} and --percentile {args.percentile} both "
                         "given: give one (a manikin is a named percentile)")
    named = MANIKINS[args.manikin] if args.manikin is not None else args.percentile
    default = BodySpec.from_percentile(defaults.PERCENTILE)
    described = {"stature", "mass", "sex", "measurements", *FLAGS} & flags
    if args.manikin is not None or "percentile" in flags or not described:
        overrides = {field: getattr(args, flag[2:]) for field, flag in BODY_FLAGS.items()
                     if flag[2:] in ("stature", "mass", "sex")
                     and getattr(args, flag[2:]) is not None}
        base = model(dataclasses.replace, BodySpec.from_percentile(named), **overrides)
    else:
        base = None
    body = model(measured_body, args, base, default.sex)
    typed = ", ".join(f"--{f.replace('_', '-')}" for f in sorted(described))
    if base is None:
        source = f"the body model's, given {typed}"
    else:
        source = f"the {args.manikin} manikin" if args.manikin is not None else \
            f"--percentile {named}" + ("" if "percentile" in flags else ", the default")
        source += f", with {typed}" if typed else ""
    # Said once the command has finished (cli.main), so that a refusal stays one line.
    args.worker_line = (f"worker: {body.sex}, {body.stature_m:.3f} m, {body.mass_kg:.1f} kg, "
                        f"elbow height {body.elbow_height_m:.3f} m ({source})")
    return body


def add_yes_argument(parser: argparse.ArgumentParser, what: str) -> None:
    """``--yes``: run work beyond the command's bound (``what``) without asking."""
    parser.add_argument("--yes", action="store_true",
                        help=f"run even when the work is larger than {what} (its estimated "
                        "time and memory are printed first)")


def check_work(args: argparse.Namespace, flag: str, amount: int, bound: int, unit: str,
               seconds: float, memory_bytes: float, too_big: bool = False) -> None:
    """Refuse work beyond ``bound`` (``amount`` of ``unit``), or ``too_big`` for memory,
    unless ``--yes``: one line with the estimate, the time from a rate just measured on this
    machine (``seconds`` in all) and the memory it needs at once."""
    if amount <= bound and not too_big:
        return
    hours = seconds / 3600
    estimate = (f"about {hours:,.1f} h" if hours >= 1 else f"about {hours * 60:,.0f} min") + \
        f" and {memory_bytes / 1e9:,.1f} GB of memory on this machine"
    if not args.yes:
        beyond = f"more than {bound:,}" if amount > bound else "too much memory at once"
        raise InputError(f"{flag}: {amount:,} {unit}, {beyond} ({estimate}); give --yes to "
                         "run it")
    print(f"{amount:,} {unit}: {estimate}", file=sys.stderr)


def add_lift_arguments(parser: argparse.ArgumentParser) -> None:
    """One flag per :class:`~ergohandover.workload.lifting.LiftTask` field: what the lifting
    equation needs beyond the box's location."""
    from ..workload.lifting import LiftTask

    add_dataclass_arguments(parser, LiftTask, "lifting task (the revised NIOSH equation)")


def lift_from_args(args: argparse.Namespace):
    """The LiftTask the lifting flags describe."""
    from ..workload.lifting import LiftTask

    return dataclass_from_args(LiftTask, args)


def add_shift_arguments(parser: argparse.ArgumentParser) -> None:
    """The shift of handovers whose fatigue the shift columns give (docs/workload.md)."""
    from ..workload.fatigue import Shift

    group = parser.add_argument_group("a shift of handovers (the three-compartment fatigue "
                                      "model; docs/workload.md)")
    group.add_argument("--rate", type=number(0, None, "a minute", above=True),
                       default=Shift.rate_per_min, metavar="PER_MIN",
                       help=f"handovers a minute (default: {Shift.rate_per_min:g})")
    group.add_argument("--hold", type=number(0, None, "s", above=True), default=Shift.hold_s,
                       metavar="S", help="seconds each handover loads the joints, below the "
                       f"cycle of 60/--rate s (default: {Shift.hold_s:g})")
    group.add_argument("--shift-hours", type=number(0, 24, "h", above=True),
                       default=Shift.hours, metavar="H",
                       help=f"the shift's length (default: {Shift.hours:g})")


def shift_from_args(args: argparse.Namespace):
    """The Shift the shift flags describe; a hold that leaves no rest before the next handover
    is refused in one line naming both flags."""
    from ..workload.fatigue import Shift

    cycle = 60.0 / args.rate
    if args.hold >= cycle:
        raise InputError(f"--hold {args.hold:g} is not allowed with --rate {args.rate:g}: a "
                         f"handover every {cycle:g} s leaves no rest (a hold below {cycle:g} s, "
                         f"or --rate below {60.0 / args.hold:g})")
    return Shift(args.rate, args.hold, args.shift_hours)


def add_task_arguments(parser: argparse.ArgumentParser) -> None:
    """One flag per :class:`~ergohandover.twin.task.TaskSpec` field: the box and ``--gaze``
    (whose default is the study's)."""
    from ..twin.task import TaskSpec

    add_dataclass_arguments(parser, TaskSpec, "task (default: the study's box and gaze)",
                            overrides={"gaze": defaults.GAZE})


def task_from_args(args: argparse.Namespace):
    """The TaskSpec the task flags describe."""
    from ..twin.task import TaskSpec

    return dataclass_from_args(TaskSpec, args)


def model_flags() -> list[str]:
    """The destinations of every flag that describes the worker, the task and the model."""
    from ..twin.task import TaskSpec

    return ["percentile", "manikin", "stature", "mass", "sex", "elbow_height", "arm_length",
            "shoulder_height", "measurements", "proportions", *(f.name for f in dataclasses.fields(
        TaskSpec)), "solver", "trunk_reference"]


def model_flags_given(args: argparse.Namespace) -> list[str]:
    """The worker, task and model flags given on the command line (``--gaze``, ...)."""
    return [f"--{dest.replace('_', '-')}" for dest in model_flags() if dest in given(args)]


def add_evaluator_arguments(parser: argparse.ArgumentParser, solver: bool = True) -> None:
    """The worker, the task, the trunk-angle reference and (``solver``) the posture solver:
    everything an :class:`~ergohandover.twin.evaluate.Evaluator` is built from."""
    from ..twin.evaluate import SOLVERS, TRUNK_REFERENCES

    add_body_arguments(parser)
    add_task_arguments(parser)
    group = parser.add_argument_group("model")
    if solver:
        group.add_argument("--solver", type=choice(SOLVERS), default=defaults.SOLVER,
                           metavar="|".join(SOLVERS),
                           help="whole-body: the twin's own solver (balance, gaze, palms; "
                           "compiled); pybullet: PyBullet's IK on the hands only "
                           f"(default: {defaults.SOLVER})")
    group.add_argument("--trunk-reference", type=choice(TRUNK_REFERENCES),
                       default=defaults.TRUNK_REFERENCE, metavar="|".join(TRUNK_REFERENCES),
                       help="trunk flexion and side bend from vertical (the worksheets') or "
                       f"relative to the pelvis (default: {defaults.TRUNK_REFERENCE})")


def evaluator_from_args(args: argparse.Namespace):
    """The Evaluator the flags describe (see :func:`add_evaluator_arguments`)."""
    from ..twin.evaluate import Evaluator

    solver = getattr(args, "solver", defaults.SOLVER)
    return model(Evaluator, body_from_args(args), task_from_args(args), solver,
                 trunk_reference=args.trunk_reference)


def add_grid_arguments(parser: argparse.ArgumentParser, boundary_help: str,
                       step_help: str) -> None:
    """``--boundary`` and ``--step`` with the study's defaults."""
    from ..landscape.grid import BOUNDARY_NAMES

    parser.add_argument("--boundary", type=boundary(BOUNDARY_NAMES), default=defaults.BOUNDARY,
                        metavar="|".join(BOUNDARY_NAMES) + "|X0,X1,Y0,Y1,Z0,Z1",
                        help=f"{boundary_help} (default: {defaults.BOUNDARY})")
    parser.add_argument("--step", type=number(0, None, "m", above=True), default=defaults.STEP,
                        metavar="S", help=f"{step_help} (default: {defaults.STEP:g})")


def grid_from_args(evaluator, boundary, step: float):
    """The grid of a boundary (its ``--boundary`` text, or a Boundary) and step; a step larger
    than the boundary names ``--step``."""
    from ..landscape.grid import Grid, parse_boundary

    if isinstance(boundary, str):
        boundary = model(parse_boundary, boundary, evaluator.body, evaluator.task)
    return model(Grid, boundary, step)


def add_landscape_argument(parser: argparse.ArgumentParser) -> None:
    """``--landscape FILE``, read by :func:`obtain_landscape` (``baseline``, ``view``)."""
    parser.add_argument("--landscape", type=existing_file, metavar="FILE",
                        help="a landscape .npz (default: the matching one from the landscape "
                        "cache, swept into it when missing)")


def obtain_landscape(args, evaluator):
    """The given landscape (checked against the flags), or the landscape door's (from the
    cache, swept into it when missing): the landscape and where it lives."""
    import sys

    from ..landscape import landscape_key
    from ..landscape.store import landscape_of

    if args.landscape is not None:
        landscape = read_landscape(args.landscape, "--landscape")
        flags = given(args)  # the grid is the landscape's own but for what a flag says
        grid = grid_from_args(
            evaluator, args.boundary if "boundary" in flags else landscape.grid.boundary,
            args.step if "step" in flags else landscape.grid.step)
        if landscape.key != landscape_key(evaluator, grid):
            raise InputError(f"--landscape {args.landscape} was made with other settings "
                             f"(worker, boundary, step or version; key {landscape.key}, "
                             f"expected {landscape_key(evaluator, grid)}); omit --landscape "
                             "to sweep the matching one")
        return landscape, args.landscape
    grid = grid_from_args(evaluator, args.boundary, args.step)
    print(f"landscape: {grid.describe()}", file=sys.stderr)
    landscape = landscape_of(evaluator, grid, workers=args.workers)
    print(f"landscape: {landscape.path}", file=sys.stderr)
    return landscape, landscape.path


def add_workers_argument(parser: argparse.ArgumentParser, what: str) -> None:
    parser.add_argument("--workers", type=whole(1), default=os.cpu_count() or 1, metavar="N",
                        help=f"{what} (default: all cores, {os.cpu_count() or 1} here)")


def add_output_folder_argument(parser: argparse.ArgumentParser, help: str,
                               flag: str = "--output") -> None:
    """A folder to write into: refused while parsing if a file is in the way."""
    parser.add_argument(flag, type=output_folder, metavar="DIR", help=help)


def add_gui_argument(parser: argparse.ArgumentParser, what: str) -> None:
    """``--gui``: once the command's outputs are written, PyBullet's own window showing
    ``what``; refused before any work where there is no display."""
    parser.add_argument("--gui", action="store_true",
                        help=f"after writing the outputs, show {what} in PyBullet's own window "
                        "and wait until it is closed (or Ctrl-C); needs a display (DISPLAY or "
                        "WAYLAND_DISPLAY), else `ergohandover view` shows the scene in a "
                        "browser (default: no window)")


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


def writable(path: str | Path) -> Path:
    """``path``, its folder created: an output is written only once everything was computed, so
    a bad input never leaves a folder behind."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return path


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

