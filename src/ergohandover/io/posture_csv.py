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

from ..ergonomics.posture import COLUMNS, POSTURE_COLUMNS, Posture, PostureError
from .csv_input import InputError, numeric_columns, read_csv_text

UNSEEN_COLUMN = "unseen"
"""The column in which `score --keypoints` names each row's unseen columns (``;``-joined); a
file with it may leave those columns' cells empty."""
UNSEEN_HINT = ("; an empty cell is a column the capture could not see (`score --keypoints` "
               "leaves them empty and names them in its 'unseen' column): keep that column, "
               "score the keypoints again with --assume COLUMN=VALUE, or fill the cell")
"""What a Posture CSV's empty cell is refused with, in a file without an 'unseen' column: where
such cells come from, and the ways out."""
UNDECLARED_HINT = ("; the row's 'unseen' cell does not name this column (an empty cell is "
                   "unseen only where it does)")
"""The same in a file with an 'unseen' column: a cell emptied by hand is not taken as unseen."""


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
    """Read and validate a Posture CSV whose every cell is given.

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
        value; a file that leaves columns unseen (:func:`read_open_postures`) names them.
    """
    frame, posture, unseen = read_open_postures(source, what, radians, radians_flag)
    if unseen is not None and unseen.any():
        names = [c for c, seen in zip(POSTURE_COLUMNS, unseen.any(axis=0), strict=True) if seen]
        rows = int(unseen.any(axis=1).sum())
        raise InputError(f"{what}: {rows} of {len(frame)} rows leave columns unseen (empty, as "
                         f"its 'unseen' column says): {', '.join(names)}; every column is "
                         "needed here: score the keypoints again with --assume COLUMN=VALUE "
                         "for each, or fill them")
    return frame, posture


def read_open_postures(source: str | os.PathLike | IO[str], what: str = "input",
                       radians: bool | None = False, radians_flag: str | None = None
                       ) -> tuple[pd.DataFrame, Posture, np.ndarray | None]:
    """Read and validate a Posture CSV that may leave columns unseen: a file with an
    ``unseen`` column (as `score --keypoints` writes) may leave empty the cells of the columns
    that column names in their row.

    Args:
        source, what, radians, radians_flag: as :func:`read_postures`.

    Returns:
        The file's cells as text, the postures (an unseen value is 0, never to be read as
        measured) and the unseen mask, (N, len(POSTURE_COLUMNS)) bool (None: the file has no
        ``unseen`` column). A column the ``unseen`` cell names but the row gives is measured.

    Raises:
        InputError, PostureError: as :func:`read_postures`; also a name in ``unseen`` that is
        not a Posture column, and an empty cell its row's ``unseen`` does not name.
    """
    frame = read_csv_text(source, what)
    declared = _declared(frame, what) if UNSEEN_COLUMN in frame.columns else None
    cells, unseen = frame, None
    if declared is not None:
        cells, unseen = frame.copy(), declared.copy()
        for i, name in enumerate(POSTURE_COLUMNS):
            if name in frame.columns:
                empty = declared[:, i] & (frame[name].str.strip() == "").to_numpy()
                cells.loc[empty, name] = "0"  # a stand-in the mask keeps from being read
                unseen[:, i] = empty
    try:
        columns = numeric_columns(cells, {c.name: c.allowed for c in COLUMNS}, what,
                                  UNSEEN_HINT if declared is None else UNDECLARED_HINT)
        posture = Posture(angle_unit_checked(columns, what, radians, radians_flag))
    except PostureError as exc:  # the posture's own checks name the row and column, not the file
        raise PostureError(f"{what}: {exc}", exc.row, exc.column, exc.value) from None
    return frame, posture, unseen


def _declared(frame: pd.DataFrame, what: str) -> np.ndarray:
    """(N, len(POSTURE_COLUMNS)) bool: the columns each row's ``unseen`` cell names."""
    index = {name: i for i, name in enumerate(POSTURE_COLUMNS)}
    out = np.zeros((len(frame), len(POSTURE_COLUMNS)), dtype=bool)
    for row, cell in enumerate(frame[UNSEEN_COLUMN]):
        for name in filter(None, (n.strip() for n in cell.split(";"))):
            if name not in index:
                raise InputError(f"{what}: row {row + 1}, column '{UNSEEN_COLUMN}': {name!r} is "
                                 "not a Posture column (expected the row's unseen Posture "
                                 "columns joined by ';', as `score --keypoints` writes them)")
            out[row, index[name]] = True
    return out
