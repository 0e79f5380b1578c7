"""A captured posture: the Posture columns measured from keypoints, what the user states they
know, and which columns stay unseen; and its scores, exact where nothing they depend on is
unseen, else an interval or a distribution (:mod:`.unseen`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from ..ergonomics import Posture, ScoringSettings, score_postures
from ..ergonomics.posture import POSTURE_COLUMNS, REQUIRED_COLUMNS
from ..errors import ErgohandoverError
from .angles import NEUTRAL_CLAVICLE_DEG, measure
from .formats import KeypointFormat
from .unseen import SCORES, score_distributions, score_intervals


class MeasuredColumnError(ErgohandoverError, ValueError):
    """A value assumed for a column the keypoints measure; the message is one line."""

    def __init__(self, message: str, column: str):
        super().__init__(message)
        self.column = column

    @classmethod
    def of(cls, column: str, seen: int, frames: int) -> MeasuredColumnError:
        """The error of ``column`` assumed while measured in ``seen`` of ``frames`` frames."""
        return cls(f"{column} is measured in {seen} of {frames} frames: an assumed value fills "
                   "only a column the capture cannot see", column)


MODES = ("interval", "prior")
"""How unseen columns enter the scores: the interval over their plausible ranges, or the
distribution under the uniform prior (:mod:`.unseen`)."""


class Captured(NamedTuple):
    """N captured postures.

    Attributes:
        columns: every Posture column, (N,) each; unseen values are 0 (never read as measured).
        unseen: (N, len(POSTURE_COLUMNS)) bool, True where a column was neither measured nor
            assumed.
    """

    columns: dict[str, np.ndarray]
    unseen: np.ndarray

    def unseen_names(self) -> list[str]:
        """Per row, the unseen columns joined by ``;`` (empty where every one is measured)."""
        names = np.array(POSTURE_COLUMNS, dtype=object)
        return [";".join(names[row]) for row in self.unseen]


def capture(points: np.ndarray, fmt: KeypointFormat, up: str | None = None,
            assume: Mapping[str, float] | None = None,
            neutral: float | Mapping[str, float] = NEUTRAL_CLAVICLE_DEG) -> Captured:
    """The Posture columns of N frames of keypoints.

    Args:
        points: (N, J, 3) keypoints [m] in ``fmt``'s joint order; NaN where a point is missing.
        fmt: their format.
        up: their up axis (default: the format's).
        assume: column -> a value the user knows, for every frame (a task factor such as
            ``load_kg``, or an angle the capture cannot see). Task factors not assumed take the
            Posture defaults (``ergohandover score --help``). A column the keypoints measure
            in any frame is a :class:`MeasuredColumnError`.
        neutral: the clavicle's slope at rest that shoulder raise is measured from [deg], for
            both sides or per side (:func:`~.angles.measure`).

    Returns:
        The columns and the unseen mask.
    """
    measured = measure(points, fmt, up, neutral)
    n = len(points)
    for name in assume or {}:
        seen = int(np.isfinite(measured[name]).sum()) if name in measured else 0
        if seen:  # an assumption fills what the capture cannot see, never a measurement
            raise MeasuredColumnError.of(name, seen, n)
    given = {name: np.zeros(n) for name in REQUIRED_COLUMNS}  # replaced by what is measured
    given |= measured
    given |= {name: np.full(n, float(value)) for name, value in (assume or {}).items()}
    unseen = np.stack([~np.isfinite(given[name]) if name in given else np.zeros(n, bool)
                       for name in POSTURE_COLUMNS], axis=1)
    # Every measured or assumed value within its column's rule; the rest at its default.
    posture = Posture({name: np.nan_to_num(v) for name, v in given.items()})
    return Captured(dict(posture), unseen)


def capture_scores(captured: Captured, settings: ScoringSettings | None = None,
                   mode: str = "interval", rng: np.random.Generator | None = None,
                   draws: int = 400) -> dict[str, np.ndarray]:
    """The scores of captured postures.

    Args:
        captured: the postures.
        settings: the scoring settings.
        mode: one of :data:`MODES`.
        rng: with ``prior``: the generator of the unseen values.
        draws: with ``prior``: values drawn per row.

    Returns:
        For each score of :data:`~.unseen.SCORES`: ``{score}`` (float; NaN where the unseen
        columns leave it open), ``{score}_lo`` and ``{score}_hi``; with ``prior`` also
        ``{score}_probabilities`` ((N, 25): the share of draws at each value).
    """
    settings = settings or ScoringSettings()
    n = captured.unseen.shape[0]
    exact = score_postures(Posture(captured.columns), settings, names=SCORES)
    out: dict[str, np.ndarray] = {}
    open_rows = np.flatnonzero(captured.unseen.any(axis=1))
    part = {name: v[open_rows] for name, v in captured.columns.items()}
    bounds = score_intervals(part, captured.unseen[open_rows], settings)
    for score in SCORES:
        lo = exact[score].astype(float)
        hi = lo.copy()
        lo[open_rows], hi[open_rows] = bounds[f"{score}_lo"], bounds[f"{score}_hi"]
        out[score] = np.where(lo == hi, lo, np.nan)
        out[f"{score}_lo"], out[f"{score}_hi"] = lo, hi
    if mode == "prior":
        rng = rng or np.random.default_rng(0)
        spread = score_distributions(part, captured.unseen[open_rows], rng, draws, settings)
        for score in SCORES:
            share = np.zeros((n, 25))
            share[np.arange(n), exact[score].astype(int)] = 1.0
            share[open_rows] = spread[f"{score}_probabilities"]
            out[f"{score}_probabilities"] = share
    return out
