"""``ergohandover score --keypoints``: a keypoint file's frames scored, each a row of the scores
CSV, and one line saying what was measured.

A wide CSV or an .npy array is read and scored a part of :data:`PART_VALUES` coordinates at a
time
(:mod:`~ergohandover.capture.large`), its rows written to a temporary file renamed at the end,
so memory stays bounded whatever the file's length and an interrupted run leaves no output; the
rows and the line are those of the whole file. The other kinds are read whole. Either way the
frames are counted first, and a file of more than :data:`MAX_FRAMES` is refused without
``--yes``.
"""

from __future__ import annotations

import argparse
import contextlib
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

from ..ergonomics import ScoringSettings
from ..ergonomics.posture import POSTURE_COLUMNS
from ..io.atomic import atomic_write
from ..io.csv_input import InputError
from .options import RUNS, body_from_args, check_work, run_folder
from .parser import given

MAX_FRAMES = 1_000_000
"""Frames a file may hold to be scored without --yes (5.5 hours of capture at 50 Hz)."""
PART_VALUES = 1_000_000
"""Coordinates read and scored at once from a file read in parts (20,000 frames of H36M-17):
while a CSV's part is parsed each of its cells is a Python string (about 400 MB for this
many), which bounds the memory a run takes."""
PROGRESS_FRAMES = 100_000
"""Files of at least this many frames show their progress (they take several seconds)."""
MAX_MEMORY_BYTES = 4e9
"""Memory a file read whole may take without --yes."""
WHOLE_TEXT_BYTES = 32
"""Memory a text file read whole takes per byte of it: every cell is a Python string while it
is parsed (a wide CSV of 87 MB took 2.7 GB)."""
PART_BYTES = 5e8
"""Memory of the program and one part of :data:`PART_VALUES` coordinates while it is read,
beyond what every frame keeps (:data:`FRAME_BYTES`): ``experiments/bench_capture_memory.py``
measures the whole."""
FRAME_BYTES = 72
"""What each frame of a file read in parts keeps to the end: its number (twice), its legs, its
height, breadth and rise for the checks and whether it misses a point."""
READ_FACTOR = {".csv": 8.0, ".json": 8.0, ".bvh": 8.0, ".npy": 1.0, ".npz": 1.0}
"""Reading a file of this kind whole takes about this many times its scoring."""
BODY_FLAGS = ("percentile", "manikin", "stature", "mass", "sex", "elbow_height", "arm_length",
              "shoulder_height", "measurements", "proportions")
"""The worker flags ``--keypoints`` reads too: the body whose resting clavicle slope is the
shoulders' neutral (:mod:`~ergohandover.capture.neutral`)."""


def keypoint_format_of(args: argparse.Namespace):
    """The format of ``--format`` (None for BVH, whose joints the file brings)."""
    from ..capture import keypoint_format

    return None if args.format == "bvh" else keypoint_format(args.format)


def seconds_per_frame(path: Path, fmt, parted: bool) -> float:
    """Seconds a frame takes on this machine: reading and scoring the file's first 2,000 frames
    when it is read in parts, else scoring 2,000 frames of random points times what reading
    the kind whole adds (:data:`READ_FACTOR`)."""
    from ..capture import capture, capture_scores, keypoint_format
    from ..capture.chunks import npy_parts, wide_csv_parts
    from ..errors import ErgohandoverError

    start = time.perf_counter()
    if parted:
        reader = wide_csv_parts(path, fmt, str(path), 1.0, 2000) if path.suffix.lower() == \
            ".csv" else npy_parts(path, 1.0, 2000)
        points = next(iter(reader)).points
    else:
        fmt = fmt or keypoint_format("smpl24")  # a BVH rig's joints are known once it is read
        points = np.random.default_rng(0).normal(0.0, 0.5, (2000, len(fmt.joints), 3))
    with contextlib.suppress(ErgohandoverError):  # a sample the checks refuse: timed so far
        capture_scores(capture(points, fmt))
    factor = 1.0 if parted else READ_FACTOR.get(path.suffix.lower(), 8.0)
    return (time.perf_counter() - start) * factor / len(points)


def check_size(args: argparse.Namespace, fmt) -> tuple[int, bool]:
    """The frames the file holds (counted or estimated) and whether it is read in parts;
    beyond :data:`MAX_FRAMES`, or too much memory read whole, refused unless ``--yes`` (one
    line with the estimate, before any work)."""
    import os

    from ..capture.chunks import count_frames, npy_layout, streamed

    path = Path(args.keypoints)
    frames = count_frames(path, len(fmt.joints) if fmt is not None else None)
    parted = streamed(path, fmt)
    if parted:
        memory = PART_BYTES + frames * FRAME_BYTES
    else:
        layout = npy_layout(path) if path.suffix.lower() == ".npy" else None
        memory = 3 * os.path.getsize(path) * (1 if path.suffix.lower() in (".npy", ".npz")
                                              else WHOLE_TEXT_BYTES / 3)
        if layout is not None:  # held as float64 and checked
            memory = 3 * 8 * int(np.prod(layout[0]))
    too_big = not parted and memory > MAX_MEMORY_BYTES
    if frames > MAX_FRAMES or too_big:
        check_work(args, f"--keypoints {args.keypoints}", frames, MAX_FRAMES,
                   "frames (estimated)", frames * seconds_per_frame(path, fmt, parted), memory,
                   too_big)
    return frames, parted


def score_keypoints(args: argparse.Namespace, settings: ScoringSettings
                    ) -> tuple[pd.DataFrame, str] | None:
    """The table of ``--keypoints`` and what it holds; None when the file was read, scored and
    written in parts (:func:`write_in_parts`)."""
    if args.joint_map is not None and args.format != "bvh":
        raise InputError(f"--joint-map cannot be used with --format {args.format} (only with "
                         "bvh: the other formats' joints are fixed)")
    body = [f"--{f.replace('_', '-')}" for f in BODY_FLAGS if f in given(args)]
    if body and args.neutral_frame is not None:
        raise InputError(f"--neutral-frame {args.neutral_frame} and {body[0]} both given: "
                         "the shoulders' neutral is a frame of the file or the body's (give "
                         "one)")
    if body and args.format == "bvh":
        raise InputError(f"{body[0]} cannot be used with --format bvh: the file's rest pose "
                         "is its body's, the shoulders' neutral (or give --neutral-frame)")
    fmt = keypoint_format_of(args)
    frames, parted = check_size(args, fmt)
    if parted:
        write_in_parts(args, settings, fmt, frames)
        return None
    return keypoint_scores(args, settings)


def assumptions(args: argparse.Namespace) -> dict[str, float]:
    """``--assume`` and ``--load-kg`` as column -> value."""
    assume = dict(args.assume or [])
    if args.load_kg is not None:
        if "load_kg" in assume:
            raise InputError("--load-kg and --assume load_kg=... both given: give one")
        assume["load_kg"] = args.load_kg
    return assume


def read_unit(args: argparse.Namespace, inferred) -> tuple[str, str, float | None]:
    """The unit the checks name, the summary's words for it, and the factor that takes a file
    read in its own unit to metres (None: ``--units`` was given and read in); ``inferred()``:
    the unit told from the legs, (name, metres per unit)."""
    if args.units is not None:
        return args.units, f"--units {args.units}", None
    name, metres = inferred()
    return f"{metres!r}", f"units {name}, told from the legs", metres


@contextlib.contextmanager
def assumed(assume: dict[str, float]):
    """``--assume`` refused in one line where it would replace a measured column."""
    from ..capture.captured import MeasuredColumnError

    try:
        yield
    except MeasuredColumnError as exc:
        raise InputError(f"--assume {exc.column}={assume[exc.column]:g}: {exc}") from None


def shoulders_neutral(args: argparse.Namespace, fmt, up: str, frames: np.ndarray,
                      points: np.ndarray | None):
    """The :class:`~ergohandover.capture.neutral.Neutral` shoulder raise is measured from:
    ``--neutral-frame`` (``points``: that frame's, None when the file lacks it), a BVH rig's
    rest pose, the body the worker flags describe, or the 50th-percentile man's."""
    from ..capture.neutral import body_neutral, default_neutral, frame_neutral, rest_neutral

    if args.neutral_frame is not None:
        return frame_neutral(frames, points, args.neutral_frame, fmt, up, str(args.keypoints))
    rest = rest_neutral(fmt, up)
    if rest is not None:
        return rest
    if any(f in given(args) for f in BODY_FLAGS):
        body = body_from_args(args)
        return body_neutral(body, "the body model's clavicle slope for the worker")
    return default_neutral()


def neutral_note(neutral, share: np.ndarray) -> str:
    """The summary line's words on the shoulders' neutral, where a shoulder raise is measured
    (``share``: per POSTURE_COLUMNS, the share of frames in which it is unseen)."""
    raise_unseen = [share[POSTURE_COLUMNS.index(f"{side}_shoulder_raise")] == 1.0
                    for side in ("left", "right")]
    return "" if all(raise_unseen) else f"; {neutral.note()}"


def frames_outside(args: argparse.Namespace, typed: str, frames: np.ndarray) -> InputError:
    last = "" if args.frames[1] == sys.maxsize else args.frames[1]
    return InputError(f"--frames {args.frames[0]}:{last}: {typed} has frames "
                      f"{frames.min()}-{frames.max()}")


def keypoint_scores(args: argparse.Namespace, settings: ScoringSettings
                    ) -> tuple[pd.DataFrame, str]:
    """The table of ``--keypoints`` read whole and what it holds, every check made before
    scoring."""
    from ..capture import capture, capture_scores
    from ..capture.bones import check_format
    from ..capture.checks import check_keypoints, infer_unit
    from ..capture.neutral import frame_row
    from ..capture.readers import read_keypoints

    typed = str(args.keypoints)
    units = args.units or "m"  # without --units: read in the file's own unit, then told
    if args.format == "bvh":
        from ..capture.bvh import JointMapError, read_bvh

        try:
            kp = read_bvh(typed, units, args.joint_map and args.joint_map.landmarks,
                          args.radians)
        except JointMapError as exc:
            raise InputError(f"--joint-map {args.joint_map.text}: {exc}") from None
    else:
        kp = read_keypoints(typed, keypoint_format_of(args), units)
    check_format(kp, typed)  # a wrong joint order, before any check that names --up or --units
    units, said, metres = read_unit(args, lambda: infer_unit(kp, typed))
    if metres is not None:
        kp = type(kp)(kp.frames, kp.points * metres, kp.fmt)
    up = args.up or kp.fmt.up
    row = frame_row(kp.frames, args.neutral_frame)
    neutral_points = None if row is None else kp.points[row]
    every_frame = kp.frames
    if args.frames is not None:
        keep = (kp.frames >= args.frames[0]) & (kp.frames <= args.frames[1])
        if not keep.any():
            raise frames_outside(args, typed, kp.frames)
        kp = type(kp)(kp.frames[keep], kp.points[keep], kp.fmt)
    missing = check_keypoints(kp, up, args.missing, typed, units)
    neutral = shoulders_neutral(args, kp.fmt, up, every_frame, neutral_points)
    assume = assumptions(args)
    with assumed(assume):
        captured = capture(kp.points, kp.fmt, up, assume, neutral.degrees)
    scores = capture_scores(captured, settings, args.unseen, np.random.default_rng(args.seed),
                            args.draws)
    table = frame_table(kp.frames, captured, scores)
    rig = f": {kp.fmt.title}" if args.format == "bvh" else ""
    return table, summary(f"{typed} ({kp.fmt.name}{rig}, up {up}, {said})", len(table),
                          int(captured.unseen.any(axis=1).sum()), kp.frames[missing],
                          captured.unseen.mean(axis=0), neutral)


def frame_table(frames: np.ndarray, captured, scores: dict[str, np.ndarray]) -> pd.DataFrame:
    """The rows of frames: the Posture columns measured (empty where unseen), the unseen
    columns' names, and every score."""
    table = pd.DataFrame({"frame": frames})
    for name in POSTURE_COLUMNS:
        values = captured.columns[name]
        table[name] = np.where(captured.unseen[:, POSTURE_COLUMNS.index(name)], np.nan, values)
    table["unseen"] = captured.unseen_names()
    for name, values in scores.items():
        if name.endswith("_probabilities"):
            table[name] = [" ".join(f"{v}:{p:.3f}" for v, p in enumerate(row) if p > 0)
                           for row in values]
        else:
            table[name] = pd.array(np.where(np.isfinite(values), values, np.nan), dtype="Int64")
    return table


def summary(source: str, frames: int, open_rows: int, missing: np.ndarray,
            share: np.ndarray, neutral) -> str:
    """What a capture measured, for its line: ``frames`` frames of ``source``, ``open_rows``
    of them with an unseen column, the frame numbers ``missing`` points, each column's share
    of frames in which it is unseen, and the shoulders' ``neutral`` where a raise is
    measured."""
    shown = ", ".join(map(str, missing[:10])) + (", …" if len(missing) > 10 else "")
    note = f"; {len(missing)} with missing points (frames {shown})" if len(missing) else ""
    return (f"{frames} frames of {source}: {frames - open_rows} with every column measured"
            f"{note}{unseen_note(share)}{neutral_note(neutral, share)}")


def unseen_note(share: np.ndarray) -> str:
    """What a capture did not measure, for its summary line: the columns unseen in every frame,
    and those unseen in some with the share of frames (``share``: per POSTURE_COLUMNS)."""
    always = [c for c, f in zip(POSTURE_COLUMNS, share, strict=True) if f == 1.0]
    some = [f"{c} ({100 * f:.0f} %)" for c, f in zip(POSTURE_COLUMNS, share, strict=True)
            if 0.0 < f < 1.0]
    return ("".join([f"; unseen in every frame: {', '.join(always)}" if always else "",
                     f"; unseen in some frames: {', '.join(some)}" if some else ""]))


def bar(desc: str, total: int) -> tqdm:
    """Progress on standard error, for files long enough to take a while."""
    return tqdm(total=total, unit="frame", unit_scale=True, desc=desc, file=sys.stderr,
                disable=total < PROGRESS_FRAMES)


def part_frames(fmt) -> int:
    """Frames in a part of :data:`PART_VALUES` coordinates of ``fmt``'s joints."""
    return max(1, PART_VALUES // (3 * len(fmt.joints)))


def write_in_parts(args: argparse.Namespace, settings: ScoringSettings, fmt,
                   estimate: int) -> None:
    """Read, check, score and write a file a part (:func:`part_frames`) at a time; every row
    and the summary line are those of :func:`keypoint_scores`, and nothing is written unless
    every frame is."""
    from ..capture.bones import check_format
    from ..capture.checks import CheckTally
    from ..capture.chunks import npy_parts, wide_csv_parts
    from ..capture.large import (
        read_parts,
        scored_parts,
        unit_of_legs,
    )
    from ..capture.readers import Keypoints, repeated_frame, unit_scale

    typed = str(args.keypoints)
    scale = unit_scale(args.units or "m", typed)  # without --units: the file's own, then told
    frames = part_frames(fmt)
    source = wide_csv_parts(typed, fmt, typed, scale, frames) \
        if Path(typed).suffix.lower() == ".csv" else npy_parts(typed, scale, frames)
    with bar("read", estimate) as shown:
        read = read_parts(source, fmt, args.frames, shown.update, args.neutral_frame)
    try:
        first = next(read.cache.parts(), None)  # the joint order, told from the first part
        if first is not None:
            check_format(Keypoints(read.kept[:len(first)], first, fmt), typed)
        repeated_frame(read.frames, typed)
        units, said, metres = read_unit(args, lambda: unit_of_legs(read.legs, fmt, typed))
        if args.frames is not None and read.kept.size == 0:
            raise frames_outside(args, typed, read.frames)
        up = args.up or fmt.up

        def parts():
            for points in read.cache.parts():
                yield points if metres is None else points * metres

        bounds = np.cumsum([0, *read.cache.sizes])
        tally = CheckTally(fmt, up)
        for k, points in enumerate(parts()):
            tally.add(read.kept[bounds[k]:bounds[k + 1]], points)
        missing = tally.verdict(args.missing, typed, units)
        # Before any part is scored: every part is measured from the same neutral.
        neutral = shoulders_neutral(args, fmt, up, read.frames, read.neutral)
        assume = assumptions(args)
        counts = np.zeros(len(POSTURE_COLUMNS), np.int64)
        open_rows = 0

        def write(handle) -> None:
            nonlocal open_rows
            at = 0
            scored = scored_parts(parts, fmt, up, assume, settings, args.unseen,
                                  np.random.default_rng(args.seed), args.draws,
                                  neutral.degrees)
            with bar("score", len(read.kept)) as shown:
                for captured, scores in scored:
                    n = len(captured.unseen)
                    table = frame_table(read.kept[at:at + n], captured, scores)
                    table.to_csv(handle, header=at == 0, index=False)
                    counts[:] += captured.unseen.sum(axis=0)
                    open_rows += int(captured.unseen.any(axis=1).sum())
                    at += n
                    shown.update(n)

        with assumed(assume):
            written = write_output(args, write)
    finally:
        read.cache.close()
    n = len(read.kept)
    line = summary(f"{typed} ({fmt.name}, up {up}, {said})", n, open_rows, read.kept[missing],
                   counts / n, neutral)
    if written is not None:
        print(f"scored {line} -> {written}", file=sys.stderr)


def write_output(args: argparse.Namespace, write) -> str | None:
    """Write the scores CSV through ``write(handle)``, all or nothing: to standard output once
    complete, or to a temporary file renamed at the end; the output's folders are made only
    for this and removed again if the writing fails. Returns the file written (None: stdout)."""
    if args.output == "-":
        with tempfile.TemporaryFile("w+", newline="") as held:
            write(held)
            held.seek(0)
            shutil.copyfileobj(held, sys.stdout)
        return None
    if args.output:
        path = Path(args.output)
        new = [p for p in [path.parent, *path.parent.parents] if not p.exists()]
    else:
        made = [p for p in (RUNS / "score", RUNS) if not p.exists()]
        path = run_folder("score") / "scores.csv"
        new = [path.parent, *made]
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(path, write)
    except BaseException:
        for folder in new:  # innermost first: only the folders made here, if left empty
            try:
                folder.rmdir()
            except OSError:
                break
        raise
    return str(path)
