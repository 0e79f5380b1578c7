"""Reading user CSV files: cells as text, numbers checked, every problem one line naming the file.

The file's bytes are read and decoded here rather than by pandas, so that a missing file, a
folder, a binary file (a landscape ``.npz`` or a picture given by mistake) or a file in another
encoding is named with what is wrong, not answered with a codec's or a tokenizer's message.
"""

from __future__ import annotations

import codecs
import csv
import io
import os
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import IO

import numpy as np
import pandas as pd

from ..errors import ErgohandoverError


class InputError(ErgohandoverError, ValueError):
    """An input file that cannot be used; the message is one line naming what is wrong."""


def read_bytes(source: str | os.PathLike, what: str, kind: str = "a CSV file") -> bytes:
    """The bytes of a file, or of standard input for ``"-"``; a one-line InputError if the file
    cannot be read (``kind``: what the file should be, for the message)."""
    if isinstance(source, str) and source == "-":
        stdin = sys.stdin
        return stdin.buffer.read() if hasattr(stdin, "buffer") else stdin.read().encode()
    path = Path(source)
    try:
        return path.read_bytes()
    except FileNotFoundError:
        raise InputError(f"{what} does not exist") from None
    except IsADirectoryError:
        raise InputError(f"{what} is a folder (expected {kind})") from None
    except PermissionError:
        raise InputError(f"{what} cannot be read (permission denied)") from None
    except OSError as exc:
        raise InputError(f"{what} cannot be read ({exc.strerror or type(exc).__name__})") \
            from None


def decode_text(data: bytes, what: str, kind: str = "CSV") -> str:
    """``data`` as UTF-8 text (a byte-order mark allowed), or UTF-16 text with its byte-order
    mark (as spreadsheets save "Unicode text"); binary data is an InputError (``kind``: the
    text's kind, for the message)."""
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            return data.decode("utf-16")
        except UnicodeDecodeError as exc:
            raise InputError(f"{what} starts as UTF-16 text but is not (bytes at position "
                             f"{exc.start}): expected a {kind} file saved as UTF-8 or "
                             "UTF-16") from None
    zero = data.find(b"\0")
    if zero >= 0:
        raise InputError(f"{what} is a binary file, not a {kind} text file (a zero byte at "
                         f"position {zero})")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{what} is not UTF-8 text (byte 0x{data[exc.start]:02x} at position "
                         f"{exc.start}): expected a {kind} file saved as UTF-8") from None


def open_source(source: str | os.PathLike | IO[str], what: str) -> IO[str]:
    """A text handle on a path, standard input (``"-"``) or an open handle (read whole, so that
    a parse error loses nothing)."""
    if hasattr(source, "read"):
        return source  # type: ignore[return-value]
    return io.StringIO(decode_text(read_bytes(source, what), what))  # type: ignore[arg-type]


SEPARATORS = {";": "semicolons", "\t": "tabs", "|": "vertical bars"}
"""Separators some spreadsheets write that a comma-separated reader would take as one column."""


def check_header(header: str, what: str) -> None:
    """Refuse a header that is not comma-separated, or that names a column twice (a reader
    would keep one of the two silently)."""
    names = [n.strip().strip('"') for n in next(csv.reader([header]), [])]
    if len(names) <= 1:
        for mark, word in SEPARATORS.items():
            if mark in header:
                raise InputError(f"{what}: its columns are separated by {word}, not commas "
                                 "(save it as comma-separated CSV)")
    seen = set()
    for name in names:
        if name and name in seen:
            raise InputError(f"{what}: column '{name}' is given twice (give each column once)")
        seen.add(name)


def read_csv_text(source: str | os.PathLike | IO[str], what: str) -> pd.DataFrame:
    """Every cell of a CSV as text; an empty file or a header with no rows is an error.

    Args:
        source: a path, ``"-"`` for stdin, or an open text handle.
        what: how to name the input in messages (its file name).
    """
    handle = open_source(source, what)
    text = handle.read()
    check_header(text.partition("\n")[0], what)
    try:
        frame = pd.read_csv(io.StringIO(text), dtype=str, keep_default_na=False,
                            skipinitialspace=True)
    except pd.errors.EmptyDataError:
        raise InputError(f"{what} is empty (expected a header row and at least one row)") \
            from None
    except pd.errors.ParserError as exc:
        detail = str(exc).strip().splitlines()[-1]
        raise InputError(f"{what} is not a well-formed CSV: {detail}") from None
    if frame.empty:
        raise InputError(f"{what} has a header but no rows")
    frame.columns = [str(c).strip() for c in frame.columns]
    return frame


def numeric_columns(frame: pd.DataFrame, allowed: Mapping[str, str],
                    what: str = "input", empty: str = "") -> dict[str, np.ndarray]:
    """The named text columns as float arrays; a cell that is not a number is an error.

    Args:
        frame: cells as text.
        allowed: column name -> what the column allows (quoted in messages); columns absent
            from ``frame`` are skipped.
        what: how to name the input in messages (its file name).
        empty: what an empty cell's message adds (where such a file usually comes from).
    """
    out = {}
    for name, expected in allowed.items():
        if name not in frame.columns:
            continue
        text = frame[name].str.strip()
        values = pd.to_numeric(text, errors="coerce").to_numpy(dtype=np.float64)
        # "nan" parses to NaN as well; the caller's own rules catch it.
        unparsed = np.flatnonzero(np.isnan(values) & (text.str.lower() != "nan").to_numpy())
        if unparsed.size:
            row = int(unparsed[0])
            cell = text.iloc[row]
            shown = repr(cell) if cell else "an empty cell"
            raise InputError(f"{what}: row {row + 1}, column '{name}': {shown} is not a number "
                             f"(expected {expected})" + (empty if not cell else ""))
        out[name] = values
    return out


def require_columns(frame: pd.DataFrame, names, what: str) -> None:
    """Raise InputError naming the first of ``names`` missing from ``frame``."""
    missing = [n for n in names if n not in frame.columns]
    if missing:
        raise InputError(f"{what} is missing required column '{missing[0]}' "
                         f"(required: {', '.join(names)})")
