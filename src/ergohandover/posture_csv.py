"""Reading a Posture CSV (DESIGN.md's contract) into a validated :class:`Posture`.

Cells are read as text, so that an error can quote exactly what the file holds, and so that
pass-through columns are written back unchanged.
"""

from __future__ import annotations

import io
import os
from typing import IO

import numpy as np
import pandas as pd

from .ergonomics.posture import COLUMN_BY_NAME, Posture, PostureError


def read_csv_text(source: str | os.PathLike | IO[str], what: str) -> pd.DataFrame:
    """Every cell of a CSV as text; an empty file or a header with no rows is an error.

    Args:
        source: a path, or an open text handle (e.g. stdin).
        what: how to name the input in messages.
    """
    try:
        frame = pd.read_csv(source, dtype=str, keep_default_na=False, skipinitialspace=True)
    except pd.errors.EmptyDataError:
        raise PostureError(f"{what} is empty (expected a header row and at least one row)") \
            from None
    except pd.errors.ParserError as exc:
        detail = str(exc).strip().splitlines()[-1]
        raise PostureError(f"{what} is not a well-formed CSV: {detail}") from None
    if frame.empty:
        raise PostureError(f"{what} has a header but no rows")
    frame.columns = [str(c).strip() for c in frame.columns]
    return frame


def numeric_columns(frame: pd.DataFrame, names: list[str]) -> dict[str, np.ndarray]:
    """The named text columns as float arrays; a cell that is not a number is an error."""
    out = {}
    for name in names:
        text = frame[name].str.strip()
        values = pd.to_numeric(text, errors="coerce").to_numpy(dtype=np.float64)
        # "nan" parses to NaN as well; it is caught, with the rest, by the column's rule.
        unparsed = np.flatnonzero(np.isnan(values) & (text.str.lower() != "nan").to_numpy())
        if unparsed.size:
            row = int(unparsed[0])
            cell = text.iloc[row]
            shown = repr(cell) if cell else "an empty cell"
            raise PostureError(
                f"row {row + 1}, column '{name}': {shown} is not a number "
                f"(expected {COLUMN_BY_NAME[name].allowed})",
                row=row + 1, column=name, value=cell,
            )
        out[name] = values
    return out


def read_postures(source: str | os.PathLike | IO[str],
                  what: str = "input") -> tuple[pd.DataFrame, Posture]:
    """Read and validate a Posture CSV.

    Args:
        source: a path, ``"-"`` for stdin, or an open text handle.
        what: how to name the input in messages (the file name, say).

    Returns:
        The file's cells as text (every column, in file order) and the validated postures.

    Raises:
        PostureError: with a one-line message naming the row, column and value at fault.
    """
    if isinstance(source, str) and source == "-":
        import sys

        source = io.StringIO(sys.stdin.read())
    frame = read_csv_text(source, what)
    known = [c for c in frame.columns if c in COLUMN_BY_NAME]
    posture = Posture(numeric_columns(frame, known))
    return frame, posture
