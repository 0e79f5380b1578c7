"""The Posture table: N postures as named numpy columns, validated once at the boundary.

Columns follow the Posture CSV contract (docs/architecture.md, File contracts). Angles are in
degrees, signed flexion +, extension −; side bend, twist, abduction, rotation, deviation may be
signed (scorers use the magnitude); shoulder raise is the clavicle's elevation above the body's
own resting slope, + up, − down (scorers count only elevation: a depressed shoulder is not
raised). Task factors and flags are optional and take documented defaults.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import ErgohandoverError

SIDES = ("left", "right")


@dataclass(frozen=True)
class Column:
    """How one Posture column is validated.

    Attributes:
        name: column name in the Posture CSV.
        kind: ``angle`` (finite, within ±180°), ``flag`` (0 or 1), ``level`` (integer 0–3) or
            ``load`` (finite, ≥ 0 kg).
        default: value used when the column is absent; ``None`` makes the column required
            unless ``same_as`` is given.
        same_as: the column whose values an absent column takes (a worksheet item that is
            usually the same for two body groups).
    """

    name: str
    kind: str
    default: float | None = None
    same_as: str | None = None

    @property
    def allowed(self) -> str:
        return {
            "angle": "a finite angle in degrees within -180..180",
            "flag": "0 or 1",
            "level": "an integer 0-3",
            "load": "a finite load in kg >= 0",
        }[self.kind]


ARM_ANGLES = (
    "upper_arm_flexion",
    "upper_arm_abduction",
    "upper_arm_rotation",
    "shoulder_raise",
    "elbow_flexion",
    "wrist_flexion",
    "wrist_deviation",
    "wrist_twist",
)

COLUMNS: tuple[Column, ...] = (
    *(Column(n, "angle") for n in (
        "trunk_flexion", "trunk_side_bend", "trunk_twist",
        "neck_flexion", "neck_side_bend", "neck_twist",
        "left_knee_flexion", "right_knee_flexion",
    )),
    Column("bilateral_support", "flag", 1),
    # REBA's legs when sitting: 1, with no knee adjustment (Hignett & McAtamney 2000).
    Column("seated", "flag", 0),
    # The load and RULA's muscle use of the arm-and-wrist group (RULA steps 8-9) and REBA's load.
    Column("load_kg", "load", 0),
    Column("shock", "flag", 0),
    Column("coupling", "level", 0),
    Column("activity", "level", 0),
    Column("hands_above_neck", "flag", 0),
    # RULA's muscle-use input (static > 1 min or repeated > 4x/min); not in REBA.
    Column("muscle_use", "flag", 0),
    # RULA's neck-trunk-leg group may differ (its steps 13-14); absent, it is the arm group's.
    Column("neck_trunk_legs_muscle_use", "flag", same_as="muscle_use"),
    Column("neck_trunk_legs_load_kg", "load", same_as="load_kg"),
    *(Column(f"{side}_{n}", "angle") for side in SIDES for n in ARM_ANGLES),
    *(Column(f"{side}_arm_supported", "flag", 0) for side in SIDES),
    # RULA's lower-arm +1: the hand works across the body's midline or out to the side.
    *(Column(f"{side}_arm_across_midline", "flag", 0) for side in SIDES),
)
COLUMN_BY_NAME: dict[str, Column] = {c.name: c for c in COLUMNS}
POSTURE_COLUMNS: tuple[str, ...] = tuple(c.name for c in COLUMNS)
REQUIRED_COLUMNS: tuple[str, ...] = tuple(
    c.name for c in COLUMNS if c.default is None and c.same_as is None)


class PostureError(ErgohandoverError, ValueError):
    """A posture value or column that cannot be scored; the message is one line.

    Attributes:
        row: 1-based data row (header excluded), or ``None`` for a whole-table problem.
        column: the column at fault, or ``None``.
        value: the offending value as text, or ``None``.
    """

    def __init__(self, message: str, row: int | None = None, column: str | None = None,
                 value: str | None = None):
        super().__init__(message)
        self.row, self.column, self.value = row, column, value


def _first_bad(values: np.ndarray, column: Column) -> int | None:
    """Index of the first value that breaks the column's rule, or None."""
    with np.errstate(invalid="ignore"):
        if column.kind == "angle":
            bad = ~(np.abs(values) <= 180.0)
        elif column.kind == "flag":
            bad = ~((values == 0) | (values == 1))
        elif column.kind == "level":
            bad = ~((values >= 0) & (values <= 3) & (values == np.round(values)))
        else:  # load
            bad = ~(np.isfinite(values) & (values >= 0))
    idx = np.flatnonzero(bad)
    return int(idx[0]) if idx.size else None


class Posture(Mapping[str, np.ndarray]):
    """N postures as a read-only mapping from column name to a float64 array of shape (N,).

    Every column of :data:`POSTURE_COLUMNS` is present (absent optional ones are filled with
    their defaults, or their ``same_as`` column's values); each value has been checked against
    its column's rule.
    """

    def __init__(self, columns: Mapping[str, np.typing.ArrayLike]):
        missing = [n for n in REQUIRED_COLUMNS if n not in columns]
        if missing:
            raise PostureError(
                f"missing required column '{missing[0]}' (required: {', '.join(missing)})",
                column=missing[0],
            )
        lengths = {np.shape(columns[n]) for n in POSTURE_COLUMNS if n in columns}
        if len(lengths) != 1 or len(next(iter(lengths))) != 1:
            raise PostureError(f"posture columns must be 1-D of one length, got shapes {lengths}")
        (n,) = next(iter(lengths))
        data: dict[str, np.ndarray] = {}
        for col in COLUMNS:
            if col.name in columns:
                # A view, so that marking it read-only leaves the caller's array writable.
                values = np.asarray(columns[col.name], dtype=np.float64).view()
                bad = _first_bad(values, col)
                if bad is not None:
                    shown = f"{values[bad]:g}"
                    raise PostureError(
                        f"row {bad + 1}, column '{col.name}': {shown} is not allowed "
                        f"(expected {col.allowed})",
                        row=bad + 1, column=col.name, value=shown,
                    )
            elif col.same_as is not None:
                values = data[col.same_as].copy()
            else:
                values = np.full(n, float(col.default))
            values.setflags(write=False)
            data[col.name] = values
        self._data = data
        self.n = n

    def __getitem__(self, name: str) -> np.ndarray:
        return self._data[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def arm(self, side: str, name: str) -> np.ndarray:
        """One arm's column, e.g. ``arm("left", "elbow_flexion")``."""
        return self._data[f"{side}_{name}"]

    def take(self, index: np.ndarray) -> Posture:
        """The postures at ``index`` (an integer array or slice), as a new Posture."""
        return Posture({k: v[index] for k, v in self._data.items()})

    @classmethod
    def random(cls, n: int, rng: np.random.Generator) -> Posture:
        """N postures drawn uniformly over ranges wide enough to reach every score band.

        Args:
            n: number of postures.
            rng: the generator to draw from (the caller owns the seed).
        """
        cols: dict[str, np.ndarray] = {}
        for col in COLUMNS:
            if col.kind == "angle":
                cols[col.name] = rng.uniform(-90.0, 150.0, n)
            elif col.kind == "flag":
                cols[col.name] = rng.integers(0, 2, n).astype(np.float64)
            elif col.kind == "level":
                cols[col.name] = rng.integers(0, 4, n).astype(np.float64)
            else:
                cols[col.name] = rng.uniform(0.0, 15.0, n)
        return cls(cols)
