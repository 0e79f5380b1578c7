"""A keypoint file scored a part at a time, in memory bounded by the part, with the results the
whole file gives.

What the whole file decides is gathered over its parts: the unit told from the median length of
the legs (:func:`~.checks.infer_unit`), the checks of :func:`~.checks.check_keypoints` (medians
over every frame: :class:`~.checks.CheckTally`), repeated frame numbers, and the assumed columns
that are measured. A first reading parses the file once and keeps its points, in metres' binary
form, in a temporary file; the checks and the scores read that file back part by part. With
``--unseen prior`` the parts' open rows are handed to :func:`~.unseen.score_distributions` in
whole blocks, so each row gets the draws it gets when the file is scored whole.

A file with several faults may be refused for another one of them than when read whole (a part
is checked before the next is read); a file with one is refused with the same line.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass

import numpy as np

from ..ergonomics import ScoringSettings
from .angles import NEUTRAL_CLAVICLE_DEG
from .captured import Captured, MeasuredColumnError, capture, capture_scores
from .checks import infer_unit, leg_lengths
from .chunks import Part
from .formats import KeypointFormat
from .neutral import frame_row
from .readers import Keypoints
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
            row = frame_row(part.frames, neutral_frame) if neutral is None else None
            if row is not None:
                neutral = part.points[row].copy()
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
