"""Reading a Posture CSV (DESIGN.md's contract) into a validated :class:`Posture`.

Cells are read as text, so that an error can quote exactly what the file holds, and so that
pass-through columns are written back unchanged.
"""

from __future__ import annotations

import os
from typing import IO

import pandas as pd

from ..ergonomics.posture import COLUMNS, Posture
from .csv_input import numeric_columns, read_csv_text


def read_postures(source: str | os.PathLike | IO[str],
                  what: str = "input") -> tuple[pd.DataFrame, Posture]:
    """Read and validate a Posture CSV.

    Args:
        source: a path, ``"-"`` for stdin, or an open text handle.
        what: how to name the input in messages (the file name, say).

    Returns:
        The file's cells as text (every column, in file order) and the validated postures.

    Raises:
        InputError, PostureError: with a one-line message naming the row, column and value.
    """
    frame = read_csv_text(source, what)
    posture = Posture(numeric_columns(frame, {c.name: c.allowed for c in COLUMNS}))
    return frame, posture
