"""Reading user CSV files: cells as text, numbers checked, every problem one line."""

from __future__ import annotations

import io
import os
import sys
from collections.abc import Mapping
from typing import IO

import numpy as np
import pandas as pd

from ..errors import ErgohandoverError


class InputError(ErgohandoverError, ValueError):
    """An input file that cannot be used; the message is one line naming what is wrong."""


def open_source(source: str | os.PathLike | IO[str]) -> str | os.PathLike | IO[str]:
    """``"-"`` means standard input (read whole, so that a parse error loses nothing)."""
    if isinstance(source, str) and source == "-":
        return io.StringIO(sys.stdin.read())
    return source


def read_csv_text(source: str | os.PathLike | IO[str], what: str) -> pd.DataFrame:
    """Every cell of a CSV as text; an empty file or a header with no rows is an error.

    Args:
        source: a path, ``"-"`` for stdin, or an open text handle.
        what: how to name the input in messages.
    """
    try:
        frame = pd.read_csv(open_source(source), dtype=str, keep_default_na=False,
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


def numeric_columns(frame: pd.DataFrame, allowed: Mapping[str, str]) -> dict[str, np.ndarray]:
    """The named text columns as float arrays; a cell that is not a number is an error.

    Args:
        frame: cells as text.
        allowed: column name -> what the column allows (quoted in messages); columns absent
            from ``frame`` are skipped.
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
            raise InputError(f"row {row + 1}, column '{name}': {shown} is not a number "
                             f"(expected {expected})")
        out[name] = values
    return out


def require_columns(frame: pd.DataFrame, names, what: str) -> None:
    """Raise InputError naming the first of ``names`` missing from ``frame``."""
    missing = [n for n in names if n not in frame.columns]
    if missing:
        raise InputError(f"{what} is missing required column '{missing[0]}' "
                         f"(required: {', '.join(names)})")
