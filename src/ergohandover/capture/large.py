"""A keypoint file scored a part at a time, in memory bounded by the part, with the results the
whole file gives.

What the whole file decides is gathered over its parts: the unit told from the median length of
the legs (:func:`~.checks.infer_unit`), the checks of :func:`~.checks.check_keypoints` (medians
over every frame), repeated frame numbers, and the assumed columns that are measured. A first
reading parses the file once and keeps its points, in metres' binary form, in a temporary file;
the checks and the scores read that file back part by part. With ``--unseen prior`` the parts'
open rows are handed to :func:`~.unseen.score_distributions` in whole blocks, so each row gets
the draws it gets when the file is scored whole.

A file with several faults may be refused for another one of them than when read whole (a part
is checked before the next is read); a file with one is refused with the same line.
"""

from __future__ import annotations

import os
import tempfile
import warnings
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field

import numpy as np

from ..ergonomics import ScoringSettings
from .angles import NEUTRAL_CLAVICLE_DEG
from .captured import Captured, MeasuredColumnError, capture, capture_scores
from .checks import (
    MAX_HEIGHT_M,
    MAX_LYING_RATIO,
    MIN_HEIGHT_M,
    TYPICAL_HEIGHT_M,
    infer_unit,
    leg_lengths,
)
from .chunks import Part
from .formats import UP_AXES, KeypointFormat, z_up
from .readers import KeypointFileError, Keypoints, unit_scale
from .unseen import SCORES, draw_block, score_distributions

Progress = Callable[[int], None]


def unit_of_legs(legs: list[np.ndarray], fmt: KeypointFormat, what: str) -> tuple[str, float]:
    """:func:`~.checks.infer_unit` of a file whose frames' legs are ``legs``: one frame whose
    legs are their median is handed to it, so that its rule and its words are the ones used.
    A straight leg along x keeps its length exactly (the square root of a rounded square is the
    number again)."""
    found = np.concatenate(legs) if legs else np.array([np.nan])
    leg = float(np.nanmedian(found)) if np.isfinite(found).any() else float("nan")
    points = np.full((1, len(fmt.joints), 3), np.nan)
    for side in ("left", "right"):
        marks = [fmt.landmarks.get(f"{side}_{part}") for part in ("hip", "knee", "ankle")]
        if all(marks):
            for mark, x in zip(marks, (0.0, leg, leg), strict=True):
                points[0, [fmt.index(j) for j in mark]] = (x, 0.0, 0.0)
    return infer_unit(Keypoints(np.array([1]), points, fmt), what)


def _outside(height: float) -> str:
    """``height`` with the digits that keep it outside the allowed range as printed (as
    :func:`~.checks.check_keypoints` prints it)."""
    for digits in range(3, 10):
        shown = f"{height:.{digits}g}"
        if not MIN_HEIGHT_M <= float(shown) <= MAX_HEIGHT_M:
            return shown
    return repr(height)


@dataclass
class CheckTally:
    """:func:`~.checks.check_keypoints` gathered part by part: :meth:`add` each part's frames
    and points [m]; :meth:`verdict` raises what the whole file raises, in the same order and
    words, and returns the frames with a missing point."""

    fmt: KeypointFormat
    up: str
    infinite: str | None = None
    empty: list[np.ndarray] = field(default_factory=list)
    gaps: list[np.ndarray] = field(default_factory=list)
    first_gap: str | None = None
    height: list[np.ndarray] = field(default_factory=list)
    across: list[np.ndarray] = field(default_factory=list)
    rise: list[np.ndarray] = field(default_factory=list)

    def add(self, frames: np.ndarray, points: np.ndarray) -> None:
        joints = self.fmt.joints
        infinite = np.argwhere(np.isinf(points).any(axis=2))
        if infinite.size and self.infinite is None:
            i, j = infinite[0]
            self.infinite = f"frame {frames[i]}, joint '{joints[j]}'"
        absent = np.isnan(points).any(axis=2)
        self.empty.append(frames[absent.all(axis=1)])
        gaps = absent.any(axis=1)
        self.gaps.append(gaps)
        if gaps.any() and self.first_gap is None:
            i, j = np.argwhere(absent)[0]
            self.first_gap = f"frame {frames[i]}, joint '{joints[j]}'"
        order, sign = z_up(self.up)
        p = points[..., order] * np.array([1.0, 1.0, sign])
        body = p[:, [self.fmt.index(j) for j in self.fmt.body]] if self.fmt.body else p
        with warnings.catch_warnings():  # a frame without points is refused in verdict()
            warnings.simplefilter("ignore", RuntimeWarning)
            extent = np.nanmax(body, axis=1) - np.nanmin(body, axis=1)
        self.height.append(extent[:, 2])
        self.across.append(extent[:, :2].max(axis=1))
        marks = self.fmt.landmarks
        if all(m in marks for m in ("left_shoulder", "right_shoulder", "left_ankle",
                                    "right_ankle")):
            def level(mark: str) -> np.ndarray:
                return p[:, [self.fmt.index(j) for j in marks[mark]], 2].mean(axis=1)

            self.rise.append(((level("left_shoulder") + level("right_shoulder"))
                              - (level("left_ankle") + level("right_ankle"))) / 2)

    def verdict(self, missing: str, what: str, units: str) -> np.ndarray:
        gaps = np.concatenate(self.gaps) if self.gaps else np.zeros(0, bool)
        if gaps.size == 0:
            raise KeypointFileError(f"{what} has no frames")
        if self.infinite:
            raise KeypointFileError(f"{what}: {self.infinite} has an infinite coordinate "
                                    "(expected finite numbers; NaN or an empty cell for a "
                                    "missing point)")
        empty = np.concatenate(self.empty)
        if empty.size:
            raise KeypointFileError(f"{what}: frame {empty[0]} has no points (every joint is "
                                    f"missing; {empty.size} such frame(s)): remove such frames")
        if missing == "error" and gaps.any():
            raise KeypointFileError(
                f"{what}: {self.first_gap} is missing (NaN or an empty cell; {int(gaps.sum())} "
                f"of {len(gaps)} frames miss points): --missing unseen scores such frames with "
                "the columns those points decide as unseen")
        height = float(np.median(np.concatenate(self.height)))
        if not MIN_HEIGHT_M <= height <= MAX_HEIGHT_M:
            per_unit = TYPICAL_HEIGHT_M / height / unit_scale(units, what)
            raise KeypointFileError(
                f"{what}: the body is {_outside(height)} m tall read as --units {units} (the "
                f"median extent of its points along the up axis {self.up.lstrip('-')}): "
                f"expected {MIN_HEIGHT_M:g}-{MAX_HEIGHT_M:g} m; is the up axis right (--up), "
                f"and what is the file's unit? A {TYPICAL_HEIGHT_M:g} m body would make one "
                f"unit {per_unit:.3g} m (--units {per_unit:.3g}; m, cm and mm are 1, 0.01 and "
                "0.001)")
        across = float(np.median(np.concatenate(self.across)))
        if across > MAX_LYING_RATIO * height:
            raise KeypointFileError(
                f"{what}: the body lies across the up axis '{self.up}' (a median {across:.2f} m "
                f"across it and {height:.2f} m along it): give the axis that points up "
                f"(--up {'|'.join(UP_AXES)})")
        if self.rise:
            rise = np.concatenate(self.rise)
            seen = rise[np.isfinite(rise)]
            if seen.size and float(np.median(seen)) < 0:
                flip = self.up[1:] if self.up.startswith("-") else f"-{self.up}"
                raise KeypointFileError(
                    f"{what}: the body is upside down along the up axis '{self.up}' (its "
                    f"shoulders are a median {-float(np.median(seen)):.2f} m below its "
                    f"ankles): is the up axis '{flip}'? (--up)")
        return gaps


class PointCache:
    """A file's kept points, written part by part to a temporary file and read back the same
    way: parsing text is most of the work, so it is done once."""

    def __init__(self, joints: int):
        handle, self.path = tempfile.mkstemp(prefix="ergohandover-keypoints-", suffix=".f8")
        self.file = os.fdopen(handle, "w+b")
        self.joints, self.sizes = joints, []

    def append(self, points: np.ndarray) -> None:
        self.file.write(np.ascontiguousarray(points, dtype=np.float64).tobytes())
        self.sizes.append(len(points))

    def parts(self) -> Iterator[np.ndarray]:
        self.file.flush()
        self.file.seek(0)
        for size in self.sizes:
            values = np.fromfile(self.file, dtype=np.float64, count=size * self.joints * 3)
            yield values.reshape(size, self.joints, 3)

    def close(self) -> None:
        self.file.close()
        os.unlink(self.path)


@dataclass
class ReadFile:
    """The first reading of a file: every frame number (for repeats and ``--frames``'
    message), the kept frames, their points cached, every frame's legs [file units], and the
    points of the frame asked for as the shoulders' neutral (None: not asked, or not in the
    file), kept whether or not it is scored."""

    frames: np.ndarray
    kept: np.ndarray
    cache: PointCache
    legs: list[np.ndarray]
    neutral: np.ndarray | None = None


def read_parts(parts: Iterator[Part], fmt: KeypointFormat, keep: tuple[int, int] | None,
               progress: Progress | None = None, neutral_frame: int | None = None) -> ReadFile:
    """Read every part, keeping the frames numbered within ``keep`` (inclusive) and the points
    of frame ``neutral_frame`` (its first row, as the whole reader finds it)."""
    cache = PointCache(len(fmt.joints))
    frames, kept, legs = [], [], []
    neutral = None
    try:
        for part in parts:
            frames.append(part.frames)
            if neutral is None and neutral_frame is not None:
                rows = np.flatnonzero(part.frames == neutral_frame)
                neutral = part.points[rows[0]].copy() if rows.size else None
            legs.append(leg_lengths(part.points, fmt))
            mask = slice(None) if keep is None else \
                (part.frames >= keep[0]) & (part.frames <= keep[1])
            kept.append(part.frames[mask])
            if len(kept[-1]):  # a part without kept frames is not scored at all
                cache.append(part.points[mask])
            if progress:
                progress(len(part.frames))
    except BaseException:
        cache.close()
        raise
    sides = [np.concatenate([p[s] for p in legs]) for s in range(len(legs[0]))] if legs else []
    return ReadFile(np.concatenate(frames), np.concatenate(kept), cache, sides, neutral)


def measured_assumptions(parts: Callable[[], Iterator[np.ndarray]], fmt: KeypointFormat,
                         up: str, assume: Mapping[str, float],
                         neutral: float | Mapping[str, float] = NEUTRAL_CLAVICLE_DEG) -> None:
    """The :class:`MeasuredColumnError` :func:`capture` raises for the whole file: the first
    assumed column measured in any part, with its count over every frame."""
    from .angles import measure

    seen = dict.fromkeys(assume, 0)
    total = 0
    for points in parts():
        measured = measure(points, fmt, up, neutral)
        total += len(points)
        for name in seen:
            seen[name] += int(np.isfinite(measured[name]).sum()) if name in measured else 0
    for name, count in seen.items():
        if count:
            raise MeasuredColumnError.of(name, count, total)


def scored_parts(parts: Callable[[], Iterator[np.ndarray]], fmt: KeypointFormat, up: str,
                 assume: Mapping[str, float], settings: ScoringSettings, mode: str,
                 rng: np.random.Generator, draws: int,
                 neutral: float | Mapping[str, float] = NEUTRAL_CLAVICLE_DEG
                 ) -> Iterator[tuple[Captured, dict[str, np.ndarray]]]:
    """Each part's captured postures and scores (:func:`capture`, :func:`capture_scores`),
    in order, equal to the rows the whole file gives. ``parts()`` yields the points [m];
    ``neutral`` is the shoulders' (decided before any part is scored)."""
    block = draw_block(draws)
    waiting: list[_Waiting] = []  # parts whose open rows are not all drawn yet
    queue: list[tuple[dict[str, np.ndarray], np.ndarray]] = []  # those rows' columns, unseen

    def draw(rows: int) -> None:
        """Draw the first ``rows`` queued open rows into their parts' distributions."""
        if rows == 0:
            return
        part = {name: np.concatenate([c[name] for c, _ in queue]) for name in queue[0][0]}
        hidden = np.concatenate([u for _, u in queue])
        spread = score_distributions({k: v[:rows] for k, v in part.items()}, hidden[:rows],
                                     rng, draws, settings)
        at = 0
        for entry in waiting:
            todo = entry.open_rows[entry.filled:]
            take = min(len(todo), rows - at)
            for score in SCORES:
                name = f"{score}_probabilities"
                entry.scores[name][todo[:take]] = spread[name][at:at + take]
            entry.filled += take
            at += take
        queue[:] = [({k: v[rows:] for k, v in part.items()}, hidden[rows:])]

    for points in parts():
        try:
            captured = capture(points, fmt, up, assume, neutral)
        except MeasuredColumnError:
            measured_assumptions(parts, fmt, up, assume, neutral)
            raise
        scores = capture_scores(captured, settings, "interval")
        if mode != "prior":
            yield captured, scores
            continue
        open_rows = np.flatnonzero(captured.unseen.any(axis=1))
        for score in SCORES:  # a row nothing leaves open: its one score, certain
            share = np.zeros((len(points), 25))
            share[np.arange(len(points)), scores[f"{score}_lo"].astype(int)] = 1.0
            scores[f"{score}_probabilities"] = share
        waiting.append(_Waiting(captured, scores, open_rows))
        queue.append(({k: v[open_rows] for k, v in captured.columns.items()},
                      captured.unseen[open_rows]))
        queued = sum(len(u) for _, u in queue)
        draw(queued // block * block)
        while waiting and waiting[0].filled == len(waiting[0].open_rows):
            done = waiting.pop(0)
            yield done.captured, done.scores
    draw(sum(len(u) for _, u in queue))
    for done in waiting:
        yield done.captured, done.scores


@dataclass
class _Waiting:
    """A part scored but for the distributions of its open rows (``filled`` drawn so far)."""

    captured: Captured
    scores: dict[str, np.ndarray]
    open_rows: np.ndarray
    filled: int = 0
