"""Checkers for argparse's ``type=``: the text a user typed for a flag, turned into the value a
command uses, or a :class:`BadValue` saying what is wrong with it.

A format problem (``1e3`` for a whole number, ``abc`` for a number) is told apart from a range
problem (a number outside what the model accepts), and every range and unit comes from the
model's own declaration (:func:`ergohandover.ranges.ranged` metadata, the body's range constants),
so that the command line refuses exactly what the model would, in its own words. The parser
(:mod:`.parser`) puts the flag and the value, as typed, in front of the problem.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import re
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from ..errors import ErgohandoverError


class BadValue(ErgohandoverError, argparse.ArgumentTypeError):
    """A value a flag does not accept: ``text`` as typed and the ``problem`` with it."""

    def __init__(self, text: str, problem: str):
        super().__init__(f"{text}: {problem}")
        self.text, self.problem = text, problem


def with_unit(value: float, unit: str) -> str:
    return f"{value:g} {unit}" if unit else f"{value:g}"


def rule(lo: float | None, hi: float | None, unit: str = "", above: bool = False) -> str:
    """The valid range in words: ``0-25 kg``, ``>= 1``, ``> 0 s``."""
    if lo is not None and hi is not None:
        return f"{lo:g}-{with_unit(hi, unit)}" if lo >= 0 else f"{lo:g} to {with_unit(hi, unit)}"
    if lo is not None:
        return f"{'>' if above else '>='} {with_unit(lo, unit)}"
    return f"<= {with_unit(hi, unit)}" if hi is not None else "any"


def _check_range(text: str, value: float, lo, hi, unit: str, above: bool) -> None:
    low = lo is not None and (value < lo or (above and value == lo))
    if low or (hi is not None and value > hi):
        where = "outside" if lo is not None and hi is not None else "must be"
        raise BadValue(text, f"{where} {rule(lo, hi, unit, above)}")


def whole(lo: int | None = None, hi: int | None = None, unit: str = "") -> Callable[[str], int]:
    """A whole number within [lo, hi]: ``1e3`` and ``2.5`` are format errors, not range ones."""
    def check(text: str) -> int:
        try:
            value = int(text.strip())
        except ValueError:
            raise BadValue(text, f"not a whole number (expected an integer "
                           f"{rule(lo, hi, unit)})") from None
        _check_range(text, value, lo, hi, unit, False)
        return value
    return check


def number(lo: float | None = None, hi: float | None = None, unit: str = "",
           above: bool = False) -> Callable[[str], float]:
    """A finite number within [lo, hi] (above ``lo`` if ``above``)."""
    def check(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise BadValue(text, f"not a number (expected {rule(lo, hi, unit, above)})") \
                from None
        if not math.isfinite(value):
            raise BadValue(text, f"not a finite number (expected {rule(lo, hi, unit, above)})")
        _check_range(text, value, lo, hi, unit, above)
        return value
    return check


def angle_error(text: str) -> str:
    """An instrument's angle error: a finite SD in degrees >= 0, or ``imu``."""
    if text.strip().lower() == "imu":
        return "imu"
    try:
        return f"{number(0, None, 'deg')(text):g}"
    except BadValue:
        raise BadValue(text, "not allowed (expected an SD in degrees >= 0, or imu)") from None


REACH_M = 3.0
"""Beyond this on any axis of the worker frame [m] no box is handed to a standing worker: wider
than anyone stands or reaches, so that only a unit mistake (centimetres given as metres) trips
it."""


def beyond_reach(values: Sequence[float]) -> str | None:
    """Why a worker-frame location [m] is refused (further than :data:`REACH_M` on an axis,
    with its reading in centimetres), or None."""
    if max(abs(v) for v in values) <= REACH_M:
        return None
    metres = ",".join(f"{v / 100:g}" for v in values)
    return (f"beyond any reach ({REACH_M:g} m on an axis; locations are in metres, worker "
            f"frame): centimetres? then {metres}")


def choice(options: Sequence[str]) -> Callable[[str], str]:
    """One of ``options``, spelled exactly."""
    def check(text: str) -> str:
        if text not in options:
            raise BadValue(text, f"not one of {', '.join(options)}")
        return text
    return check


UNIT_IN_HELP = re.compile(r"\[([^\]]+)\]")


def unit_of(field: dataclasses.Field) -> str:
    """A ranged field's unit: its declared one, else the ``[unit]`` of its help text."""
    meta = field.metadata
    found = UNIT_IN_HELP.search(meta.get("help", ""))
    return meta.get("unit") or (found.group(1) if found else "")


def field_value(field: dataclasses.Field) -> Callable[[str], Any]:
    """The checker of a field made with :func:`ergohandover.ranges.ranged`: its choices, or its
    range and unit, a whole number for an integer field."""
    meta = field.metadata
    if meta.get("choices") is not None:
        return choice(meta["choices"])
    if isinstance(field.default, int) and not isinstance(field.default, bool):
        return whole(meta["lo"], meta["hi"], unit_of(field))
    return number(meta["lo"], meta["hi"], unit_of(field))


def boundary(names: Sequence[str]) -> Callable[[str], str]:
    """A named boundary or six numbers ``X0,X1,Y0,Y1,Z0,Z1`` [m], each range not empty; the text
    itself is kept (it is what manifests record and what the grid is parsed from)."""
    expected = f"{', '.join(names)} or six numbers X0,X1,Y0,Y1,Z0,Z1 in metres"

    def check(text: str) -> str:
        if text in names:
            return text
        try:
            values = [float(part) for part in text.split(",")]
        except ValueError:
            values = []
        if len(values) != 6:
            raise BadValue(text, f"not {expected}")
        if not all(math.isfinite(v) for v in values):
            raise BadValue(text, f"not finite (expected {expected})")
        for axis, lo, hi in zip("xyz", values[0::2], values[1::2], strict=True):
            if not lo < hi:
                raise BadValue(text, f"the {axis} range {lo:g}..{hi:g} m is empty or inverted "
                               f"(expected {axis.upper()}0 < {axis.upper()}1)")
        return text
    return check


def point(text: str) -> tuple[float, float, float]:
    """``X,Y,Z``: three finite numbers [m], worker frame."""
    try:
        values = [float(part) for part in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise BadValue(text, "not three finite numbers X,Y,Z in metres (worker frame)")
    return tuple(values)  # type: ignore[return-value]


def existing_file(text: str) -> Path:
    """A file that exists (a folder or a missing path is refused before anything runs)."""
    path = Path(text)
    if path.is_dir():
        raise BadValue(text, "a folder, not a file")
    if not path.is_file():
        raise BadValue(text, "no such file")
    return path


def _file_in_the_way(path: Path) -> Path | None:
    """The first existing ancestor of ``path`` that is a file (so no folder can be made)."""
    for parent in reversed(path.parents):
        if parent.exists() and not parent.is_dir():
            return parent
    return None


def _can_write(text: str, folder: bool) -> None:
    """Refuse, as typed, a place nothing can be written (checked as the flag is read, so
    before any work and before any handover is asked)."""
    from ..io.atomic import OutputError, check_writable

    try:
        check_writable(text, folder=folder)
    except OutputError as exc:
        raise BadValue(text, str(exc).split(": ", 1)[1]) from None


def output_file(text: str) -> str:
    """A file to write, or ``-`` for standard output; its folder is created when written."""
    if text == "-":
        return text
    path = Path(text)
    if path.is_dir():
        raise BadValue(text, "a folder, not a file to write")
    blocker = _file_in_the_way(path)
    if blocker is not None:
        raise BadValue(text, f"'{blocker}' is a file, so no folder can be made there")
    _can_write(text, folder=False)
    return text


def output_folder(text: str) -> Path:
    """A folder to write into (created when written); an existing file is refused."""
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise BadValue(text, "a file, not a folder")
    blocker = _file_in_the_way(path)
    if blocker is not None:
        raise BadValue(text, f"'{blocker}' is a file, so no folder can be made there")
    _can_write(text, folder=True)
    return path
