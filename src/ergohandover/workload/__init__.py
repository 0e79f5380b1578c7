"""What a practitioner's tools report beside REBA and RULA — OWAS posture codes, the revised
NIOSH lifting equation, static low-back load with the share of strength it takes — and the
standard manikins they run on (:mod:`.manikins`).

These are computed from an Evaluation's or a Posture CSV's columns after scoring and are never
stored in a landscape, so they live outside :mod:`ergohandover.ergonomics`, whose source is part
of every landscape's key (docs/workload.md).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..ergonomics import Posture
from ..ergonomics.posture import POSTURE_COLUMNS
from .back import COLUMNS as BACK_COLUMNS
from .back import Levers, back_load
from .lifting import COLUMNS as LIFT_COLUMNS
from .lifting import LiftError, LiftTask, lift_at
from .owas import COLUMNS as OWAS_COLUMNS
from .owas import owas
from .strength import SHIFT_COLUMNS

WORKLOAD_COLUMNS = (*OWAS_COLUMNS, *LIFT_COLUMNS, *BACK_COLUMNS)
"""Every column :func:`workload` gives, in order (the lifting columns only with locations)."""


def workload(posture: Posture, levers: Levers, locations: np.ndarray | None = None,
             lift: LiftTask | None = None) -> dict[str, np.ndarray]:
    """OWAS, the lifting equation at ``locations`` (N, 3) [m, worker frame] when given, and
    the back load of N postures of the body with ``levers``."""
    out = owas(posture)
    if locations is not None:
        out |= lift_at(locations, posture["load_kg"], posture["coupling"], lift or LiftTask())
    return out | back_load(posture, levers)


def _rows_mask(table: pd.DataFrame, rows: np.ndarray | None) -> np.ndarray:
    """``rows`` as a boolean mask of ``table`` (every row if None)."""
    return np.ones(len(table), dtype=bool) if rows is None else np.asarray(rows, dtype=bool)


def _posture_of(chosen: pd.DataFrame) -> Posture:
    """The Posture of a table's rows (the Posture columns it has)."""
    return Posture({c: chosen[c].to_numpy(dtype=float) for c in POSTURE_COLUMNS if c in chosen})


def _spread(found: dict[str, np.ndarray], index: pd.Index, rows: np.ndarray) -> pd.DataFrame:
    """Columns computed at ``rows`` of a table, placed back on its ``index``, empty elsewhere:
    codes and bands stay whole numbers (an empty cell is pandas' missing integer)."""
    out = {}
    for name, values in found.items():
        kind = "Int64" if np.issubdtype(values.dtype, np.integer) else float
        column = pd.Series(pd.NA if kind == "Int64" else np.nan, index=index, dtype=kind)
        column[rows] = values
        out[name] = column
    return pd.DataFrame(out, index=index)


def workload_table(table: pd.DataFrame, levers: Levers, lift: LiftTask | None = None,
                   rows: np.ndarray | None = None) -> pd.DataFrame:
    """:func:`workload` of a table with the Posture columns (an Evaluation, a Posture CSV):
    with the lifting columns when it has the location columns ``x, y, z``; only at ``rows``
    (a boolean mask, e.g. the feasible rows; every row if omitted), empty elsewhere."""
    rows = _rows_mask(table, rows)
    chosen = table[rows]
    located = {"x", "y", "z"} <= set(table.columns)
    found = workload(_posture_of(chosen), levers,
                     chosen[["x", "y", "z"]].to_numpy(dtype=float) if located else None, lift)
    return _spread(found, table.index, rows)


def shift_table(table: pd.DataFrame, body, plan, rows: np.ndarray | None = None
                ) -> pd.DataFrame:
    """A shift of handovers (``plan``: a :class:`~.fatigue.Shift`) at each posture of a table
    with the Posture columns, for ``body`` (its strength): each joint's load share, first
    failure and capacity at the end, the shift's, and the low back's daily dose
    (:func:`~.strength.shift_columns`); only at ``rows`` (every row if omitted), empty
    elsewhere."""
    from .strength import shift_columns

    rows = _rows_mask(table, rows)
    return _spread(shift_columns(_posture_of(table[rows]), body, plan), table.index, rows)


__all__ = [
    "SHIFT_COLUMNS",
    "WORKLOAD_COLUMNS",
    "Levers",
    "LiftError",
    "LiftTask",
    "back_load",
    "lift_at",
    "owas",
    "shift_table",
    "workload",
    "workload_table",
]
