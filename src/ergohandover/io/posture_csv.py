"""Reading a Posture CSV (the contract of docs/architecture.md, "File contracts") into a
validated :class:`Posture`.

Cells are read as text, so that an error can quote exactly what the file holds, and so that
pass-through columns are written back unchanged.
"""

from __future__ import annotations

import math
import os
from typing import IO

import numpy as np
import pandas as pd

from ..ergonomics.posture import COLUMNS, Posture, PostureError
from .csv_input import InputError, numeric_columns, read_csv_text

UNSEEN_HINT = ("; an empty cell is a column the capture could not see (`score --keypoints` "
               "leaves them empty): score the keypoints again with --assume COLUMN=VALUE, or "
               "fill the column")
"""What a Posture CSV's empty cell is refused with: where such cells come from, and the way
out."""


RADIANS_AT_MOST = math.pi + 0.05
"""A file whose every angle lies within ± this (and some beyond :data:`NEUTRAL_DEG`) reads as
radians: in degrees, a whole file of postures within 3° of upright is not a measurement of
work."""
NEUTRAL_DEG = 0.3
"""Below this largest angle a file is upright in either unit and is taken as given."""


def angle_unit_checked(columns: dict[str, np.ndarray], what: str, radians: bool | None,
                       flag: str | None = None) -> dict[str, np.ndarray]:
    """The angle columns in degrees: converted from radians when ``radians`` is True; when it
    is False, a file that reads as radians (:data:`RADIANS_AT_MOST`) is refused in one line
    (naming ``flag``, the command's way to say so, if it has one); None takes the values as
    given (one answer's posture, too few angles to tell)."""
    angles = [c.name for c in COLUMNS if c.kind == "angle" and c.name in columns]
    if radians:
        return {**columns, **{n: np.degrees(columns[n]) for n in angles}}
    if radians is None or not angles:
        return columns
    values = np.abs(np.concatenate([columns[n] for n in angles]))
    largest = float(np.nanmax(values)) if np.isfinite(values).any() else 0.0
    if NEUTRAL_DEG < largest <= RADIANS_AT_MOST:
        name = max(angles, key=lambda n: np.nanmax(np.abs(columns[n]), initial=0.0))
        raise InputError(f"{what}: every angle is within ±{RADIANS_AT_MOST:.2f} (the largest, "
                         f"'{name}', {largest:g}): these look like radians; give the angles "
                         "in degrees (radians x 57.3)" + (f", or {flag}" if flag else ""))
    return columns


def read_postures(source: str | os.PathLike | IO[str], what: str = "input",
                  radians: bool | None = False,
                  radians_flag: str | None = None) -> tuple[pd.DataFrame, Posture]:
    """Read and validate a Posture CSV.

    Args:
        source: a path, ``"-"`` for stdin, or an open text handle.
        what: how to name the input in messages (the file name, say).
        radians: the file's angles are radians, to be converted (True); degrees, a file that
            reads as radians refused (False); or degrees taken as given (None: one row, too
            few angles to tell).
        radians_flag: the command's flag that says the angles are radians (named when a file
            is refused as radians).

    Returns:
        The file's cells as text (every column, in file order) and the validated postures.

    Raises:
        InputError, PostureError: with a one-line message naming the file, row, column and
        value.
    """
    frame = read_csv_text(source, what)
    try:
        columns = numeric_columns(frame, {c.name: c.allowed for c in COLUMNS}, what,
                                  UNSEEN_HINT)
        posture = Posture(angle_unit_checked(columns, what, radians, radians_flag))
    except PostureError as exc:  # the posture's own checks name the row and column, not the file
        raise PostureError(f"{what}: {exc}", exc.row, exc.column, exc.value) from None
    return frame, posture
