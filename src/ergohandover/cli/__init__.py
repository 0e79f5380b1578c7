"""The ``ergohandover`` command line: sub-commands, and one-line errors with exit code 2."""

from __future__ import annotations

import argparse
import sys

from .. import __version__
from ..ergonomics import PostureError, SettingsError
from ..io.atomic import OutputError
from ..io.csv_input import InputError
from ..landscape.sweep import LandscapeError
from ..twin.anthropometry import BodySpecError
from ..twin.evaluate import EvaluationError
from ..twin.task import TaskSpecError
from . import baseline, evaluate, score, sweep, train

COMMANDS = (score, evaluate, sweep, baseline, train)
# Errors caused by what the user gave us: one line on stderr, exit code 2, no traceback.
USER_ERRORS = (InputError, PostureError, SettingsError, BodySpecError, TaskSpecError,
               EvaluationError, LandscapeError, OutputError, FileNotFoundError, IsADirectoryError,
               PermissionError, UnicodeDecodeError)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ergohandover",
        description="Find where a robot should hand a box to a worker so that the worker's "
        "posture is as safe as possible, scored with REBA, RULA and the paper's score.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in COMMANDS:
        command.add_parser(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except USER_ERRORS as exc:
        message = str(exc) if not isinstance(exc, OSError) or exc.filename is None else (
            f"{exc.filename}: {exc.strerror}")
        print(f"ergohandover {args.command}: error: {message}", file=sys.stderr)
        return 2


