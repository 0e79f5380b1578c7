"""Reading a Posture CSV (the contract of docs/architecture.md, "File contracts") into a
validated :class:`Posture`.

Cells are read as text, so that an error can quote exactly what the file holds, and so that
pass-through columns are written back unchanged.
"""

from __future__ import annotations

import os
from typing import IO

import pandas as pd

from ..ergonomics.posture import COLUMNS, Posture, PostureError
from .csv_input import numeric_columns, read_csv_text

UNSEEN_HINT = ("; an empty cell is a column the capture could not see (`score --keypoints` "
               "leaves them empty): score the keypoints again with --assume COLUMN=VALUE, or "
               "fill the column")
"""What a Posture CSV's empty cell is refused with: where such cells come from, and the way
out."""


def read_postures(source: str | os.PathLike | IO[str],
                  what: str = "input") -> tuple[pd.DataFrame, Posture]:
    """Read and validate a Posture CSV.

    Args:
        source: a path, ``"-"`` for stdin, or an open text handle.
        what: how to name the input in messages (the file name, say).

    Returns:
        The file's cells as text (every column, in file order) and the validated postures.

    Raises:
        InputError, PostureError: with a one-line message naming the file, row, column and
        value.
    """
    frame = read_csv_text(source, what)
    try:
        posture = Posture(numeric_columns(frame, {c.name: c.allowed for c in COLUMNS}, what,
                                          UNSEEN_HINT))
    except PostureError as exc:  # the posture's own checks name the row and column, not the file
        raise PostureError(f"{what}: {exc}", exc.row, exc.column, exc.value) from None
    return frame, posture
