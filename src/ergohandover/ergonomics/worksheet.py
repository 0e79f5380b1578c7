"""A rater's worksheet: REBA's and RULA's tables and final scores from item scores.

An ergonomist who scores by eye fills the worksheet's items (trunk, neck, legs, upper arm, …,
each with its adjustments); the tables do the rest, and that is where sheets go wrong. This
module takes the items and looks the tables up with the same functions the angle scorers use
(:func:`~ergohandover.ergonomics.reba.reba_from_items`,
:func:`~ergohandover.ergonomics.rula.rula_from_items`).

Item columns are named as the scorers name them (:data:`ITEM_RANGES`). The worksheets score one
arm: a side-less arm item (``reba_upper_arm``) is that arm's and stands for both sides; per-side
items (``reba_left_upper_arm``) score each arm, the worse carried forward as the tables do. A
table may hold REBA's items, RULA's, or both; a sheet is scored when any of its items is given,
and then every one of them must be.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .bands import SCORE_DTYPE
from .posture import SIDES, PostureError
from .reba import ITEM_RANGES as REBA_ITEMS
from .reba import reba_from_items
from .rula import ITEM_RANGES as RULA_ITEMS
from .rula import rula_from_items

SHEETS = {"reba": (REBA_ITEMS, reba_from_items), "rula": (RULA_ITEMS, rula_from_items)}
"""Each worksheet: its items with their ranges, and what scores them."""


def arm_items(sheet: str) -> tuple[str, ...]:
    """The sheet's per-arm item names without their side (``upper_arm``, …)."""
    prefix = f"{sheet}_{SIDES[0]}_"
    return tuple(n.removeprefix(prefix) for n in SHEETS[sheet][0] if n.startswith(prefix))


def item_columns(sheet: str) -> tuple[str, ...]:
    """Every column a table of ``sheet``'s items may have: side-less arm items included."""
    return (*SHEETS[sheet][0], *(f"{sheet}_{item}" for item in arm_items(sheet)))


def _per_side(sheet: str, given: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The sheet's items with a side-less arm item copied to both sides."""
    out = dict(given)
    for item in arm_items(sheet):
        one = out.pop(f"{sheet}_{item}", None)
        if one is None:
            continue
        for side in SIDES:
            name = f"{sheet}_{side}_{item}"
            if name in given:
                raise PostureError(f"column '{sheet}_{item}' and column '{name}' both given "
                                   "(give one arm, or each side)", column=name)
            out[name] = one
    return out


def _range(sheet: str, name: str) -> tuple[int, int]:
    """The scores item ``name`` can take (a side-less arm item: its sides')."""
    ranges = SHEETS[sheet][0]
    return ranges.get(name) or ranges[name.replace(f"{sheet}_", f"{sheet}_{SIDES[0]}_", 1)]


def _checked(name: str, values: np.ndarray, lo: int, hi: int) -> np.ndarray:
    with np.errstate(invalid="ignore"):
        bad = np.flatnonzero(~((values >= lo) & (values <= hi) & (values == np.round(values))))
    if bad.size:
        row, shown = int(bad[0]) + 1, f"{values[bad[0]]:g}"
        raise PostureError(f"row {row}, column '{name}': {shown} is not allowed (expected an "
                           f"integer {lo}-{hi})", row=row, column=name, value=shown)
    return values.astype(SCORE_DTYPE)


def sheets_given(columns: Mapping[str, object]) -> tuple[str, ...]:
    """The worksheets (``reba``, ``rula``) of which ``columns`` names at least one item."""
    return tuple(s for s in SHEETS if any(c in columns for c in item_columns(s)))


def score_items(columns: Mapping[str, np.typing.ArrayLike]) -> dict[str, np.ndarray]:
    """Tables A/B/C and the final scores of N filled worksheets.

    Args:
        columns: item name -> (N,) item scores; other names are ignored.

    Returns:
        Named (N,) int8 arrays: every sheet given, as :func:`reba_from_items` and
        :func:`rula_from_items` return them (``reba``, ``reba_table_a``, …, ``rula``, …).

    Raises:
        PostureError: no item of either sheet; an item of a given sheet missing; a value that
            is not an integer within its item's range (one line naming the row and column).
    """
    sheets = sheets_given(columns)
    if not sheets:
        raise PostureError("no worksheet item columns: expected REBA's "
                           f"({', '.join(item_columns('reba'))}) or RULA's "
                           f"({', '.join(item_columns('rula'))})")
    out: dict[str, np.ndarray] = {}
    for sheet in sheets:
        ranges, tables = SHEETS[sheet]
        given = _per_side(sheet, {
            c: _checked(c, np.asarray(columns[c], dtype=np.float64), *_range(sheet, c))
            for c in item_columns(sheet) if c in columns})
        missing = [name for name in ranges if name not in given]
        if missing:
            name = f"'{missing[0]}'"
            side, _, item = missing[0].removeprefix(f"{sheet}_").partition("_")
            if side in SIDES and item in arm_items(sheet):
                name = (f"'{sheet}_{item}' (or '{sheet}_left_{item}' and "
                        f"'{sheet}_right_{item}')")
            raise PostureError(f"missing {sheet.upper()} item column {name}: a {sheet.upper()} "
                               "sheet needs every item of docs/report.md, \"A rater's "
                               "worksheet\"", column=missing[0])
        out |= tables({name: given[name] for name in ranges})
    return out
