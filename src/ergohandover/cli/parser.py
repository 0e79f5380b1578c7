"""The argument parser of every command: a bad command line is one line naming the flag as the
user typed it, never argparse's usage block, and each command can tell a flag the user gave from
its default.

argparse accepts an unambiguous abbreviation of a long flag (``--box-mass`` for
``--box-mass-kg``); a message names the flag the way it was typed, so that the user finds it in
their own command.
"""

from __future__ import annotations

import argparse
import re
import shlex
import sys

from ..errors import ErgohandoverError
from .values import BadValue

GIVEN = "flags_given"
"""The namespace attribute listing the destinations of the flags given on the command line."""


class FlagError(ErgohandoverError, ValueError):
    """A command line that cannot be run; ``prog`` is the command it was given to."""

    def __init__(self, prog: str, message: str):
        super().__init__(message)
        self.prog = prog


class Store(argparse.Action):
    """argparse's plain ``store``, which also notes that the flag was given (:func:`given`)."""

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)
        setattr(namespace, GIVEN, {*getattr(namespace, GIVEN, ()), self.dest})


def given(args: argparse.Namespace) -> set[str]:
    """The destinations of the flags the user gave (a default is not given, even if typed the
    same: use this to tell them apart)."""
    return set(getattr(args, GIVEN, ()))


class Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are :class:`FlagError` (one line each) and whose plain
    flags record that they were given. Sub-command parsers are of the same class."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("exit_on_error", False)  # errors come back to parse_known_args
        super().__init__(*args, **kwargs)
        self.register("action", None, Store)
        self.register("action", "store", Store)
        self.typed: list[str] = []
        self.commands: dict[str, Parser] = {}  # a command's parser by name (the top level's)

    def parse_known_args(self, args=None, namespace=None):
        self.typed = list(sys.argv[1:] if args is None else args)
        try:
            return super().parse_known_args(args, namespace)
        except argparse.ArgumentError as err:
            raise FlagError(self.prog, self.explain(err)) from None

    def parse_args(self, args=None, namespace=None):
        try:  # newer Pythons raise "unrecognized arguments" here rather than calling error()
            return super().parse_args(args, namespace)
        except argparse.ArgumentError as err:
            raise FlagError(self.prog, self.explain(err)) from None

    def error(self, message: str):
        raise FlagError(self.prog, self.as_typed(message))

    def explain(self, err: argparse.ArgumentError) -> str:
        """``--flag VALUE: problem`` for a value a checker refused, else ``--flag: message``."""
        name = (err.argument_name or "").split("/")[0]
        flag = self.typed_flag(name) if name.startswith("-") else name
        bad = err.__context__  # the checker's own error, which argparse wrapped
        if isinstance(bad, BadValue):  # a positional value (a file) speaks for itself
            typed = shlex.quote(bad.text)
            return f"{flag} {typed}: {bad.problem}" if name.startswith("-") else (
                f"{typed}: {bad.problem}")
        return f"{flag}: {err.message}" if flag else err.message

    def abbreviations(self) -> dict[str, str]:
        """Every long flag the user typed abbreviated: full flag -> as typed."""
        out = {}
        for token in self.typed:
            typed = token.split("=", 1)[0]
            if not typed.startswith("--") or len(typed) < 3 or typed in (
                    self._option_string_actions):
                continue
            matches = [o for o in self._option_string_actions if o.startswith(typed)]
            if len(matches) == 1:
                out[matches[0]] = typed
        return out

    def typed_flag(self, flag: str) -> str:
        """``flag`` as the user typed it."""
        return self.abbreviations().get(flag, flag)

    def as_typed(self, message: str) -> str:
        """``message`` with every flag the user abbreviated written as typed."""
        for flag, typed in self.abbreviations().items():
            message = re.sub(rf"(?<![\w-]){re.escape(flag)}(?![\w-])", typed, message)
        return message
