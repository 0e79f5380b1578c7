"""The ``ergohandover`` command line: sub-commands, and one-line errors with exit code 2."""

from __future__ import annotations

import importlib
import sys

from .. import __version__
from ..errors import ErgohandoverError
from ..executor import clean_stop
from .options import join_negative_values
from .parser import FlagError, Parser

COMMANDS = {"score": "score", "evaluate": "evaluate", "robustness": "robustness",
            "sweep": "sweep", "landscape-stats": "sweep", "baseline": "baseline",
            "train": "train", "personalise": "personalise", "view": "view", "report": "report"}
"""Each sub-command and the module that defines it, imported only when that command runs (or
for the top-level help): a command pays for what it uses, not for every other command."""
# Errors caused by what the user gave us: one line on stderr, exit code 2, no traceback.
# Every error of the package derives from ErgohandoverError; the others are the file
# system's answers about paths the user named.
USER_ERRORS = (ErgohandoverError, FileNotFoundError, IsADirectoryError, NotADirectoryError,
               PermissionError, FileExistsError, UnicodeDecodeError)


def build_parser(command: str | None = None) -> Parser:
    """The command line's parser: with ``command`` one of :data:`COMMANDS`, only its module's
    sub-commands; otherwise every one."""
    parser = Parser(
        prog="ergohandover",
        description="Find where a robot should hand a box to a worker so that the worker's "
        "posture is as safe as possible, scored with REBA, RULA and the paper's score.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    modules = [COMMANDS[command]] if command in COMMANDS else dict.fromkeys(COMMANDS.values())
    for name in modules:
        importlib.import_module(f"{__name__}.{name}").add_parser(subparsers)
    parser.commands = dict(subparsers.choices)
    for sub in parser.commands.values():
        # A run's error names flags as the user typed them: its command's parser knows how.
        sub.set_defaults(command_parser=sub)
    return parser


def fail(prog: str, message: str) -> int:
    print(f"{prog}: error: {message}", file=sys.stderr)
    return 2


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        named = next((a for a in argv if not a.startswith("-")), None)
        args = build_parser(named).parse_args(join_negative_values(argv))
    except FlagError as exc:
        return fail(exc.prog, str(exc))
    command = args.command_parser
    try:
        # Ctrl-C and kill: workers stopped, one line, exit 130 or 143.
        with clean_stop(name=command.prog):
            code = args.run(args)
        if code == 0 and getattr(args, "worker_line", None):
            print(args.worker_line, file=sys.stderr)  # the body every number is of
        return code
    except USER_ERRORS as exc:
        message = str(exc) if not isinstance(exc, OSError) or exc.filename is None else (
            f"{exc.filename}: {exc.strerror}")
        return fail(command.prog, command.as_typed(message))
