"""Keypoint files read a part at a time, and how many frames a file holds, told before it is
read.

A wide CSV and an .npy array (frames, joints, 3) are read in parts of at most a given number of
frames, each part exactly as :func:`~.readers.read_keypoints` reads those rows of the whole
file, so that what is scored part by part is what would be scored whole. The other kinds are
read whole: a long CSV (a frame's rows may be anywhere in the file), MediaPipe JSON (one JSON
document), .npz (a zip archive) and BVH (:mod:`.bvh`); their frames are still counted first.
"""

from __future__ import annotations

import codecs
import csv
import os
import re
import zipfile
from collections.abc import Iterator
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd

from ..io.csv_input import InputError, check_header, decode_text
from .formats import KeypointFormat
from .readers import KeypointFileError, cell_values, frame_numbers, whole_points

SAMPLE_BYTES = 1 << 16
"""The head of a file read to count its frames: enough lines of any format for their mean
length."""


class Part(NamedTuple):
    """Consecutive frames of a file: their numbers (N,) and points (N, J, 3) [file units / the
    reader's scale], NaN where missing."""

    frames: np.ndarray
    points: np.ndarray


def _head(path: str | os.PathLike, size: int = SAMPLE_BYTES) -> bytes:
    with open(path, "rb") as handle:
        return handle.read(size)


def _header_names(head: bytes) -> list[str]:
    """The column names of a CSV's first line (UTF-16 with its mark, else UTF-8)."""
    utf16 = head.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE))
    text = head.decode("utf-16" if utf16 else "utf-8-sig", errors="replace")
    return [n.strip().strip('"') for n in next(csv.reader([text.partition("\n")[0]]), [])]


def _npy_header(handle) -> tuple[tuple[int, ...], bool, np.dtype]:
    """(shape, Fortran order, dtype) of an .npy header; ValueError for a version NumPy does not
    read by a public function."""
    version = np.lib.format.read_magic(handle)
    read = {(1, 0): np.lib.format.read_array_header_1_0,
            (2, 0): np.lib.format.read_array_header_2_0}.get(version)
    if read is None:
        raise ValueError(f"version {version}")
    return read(handle)


def npy_layout(path: str | os.PathLike) -> tuple[tuple[int, ...], np.dtype, int] | None:
    """(shape, dtype, offset of the data) of an .npy file whose values follow its header in C
    order and fill the rest of the file; None for any other file (read whole, which says what
    is wrong with it)."""
    try:
        with open(path, "rb") as handle:
            shape, fortran, dtype = _npy_header(handle)
            offset = handle.tell()
    except (OSError, ValueError, EOFError):
        return None
    if fortran or dtype.hasobject:
        return None
    size = int(np.prod(shape)) * dtype.itemsize
    return (shape, dtype, offset) if os.path.getsize(path) == offset + size else None


def streamed(path: str | os.PathLike, fmt: KeypointFormat | None) -> bool:
    """Whether ``path`` is read a part at a time: a wide CSV, or an .npy array of ``fmt``'s
    (frames, joints, 3) numbers."""
    ext = Path(path).suffix.lower()
    if fmt is None:  # BVH
        return False
    if ext == ".csv":
        try:
            return "joint" not in _header_names(_head(path))
        except OSError:
            return False
    if ext == ".npy":
        layout = npy_layout(path)
        return layout is not None and len(layout[0]) == 3 and layout[0][0] > 0 \
            and layout[0][1:] == (len(fmt.joints), 3) and layout[1].kind in "fiu"
    return False


def count_frames(path: str | os.PathLike, joints: int | None) -> int:
    """The frames a keypoint or BVH file holds, from its header (.npy, .npz, BVH) or from its
    size and the mean length of the lines (or, in JSON, of the landmarks) at its head: an
    estimate of text files, close for any file whose frames are written alike; 0 when it cannot
    be told (the reader says why). ``joints``: the format's (None for BVH)."""
    ext = Path(path).suffix.lower()
    try:
        size = os.path.getsize(path)
        head = _head(path, 1 << 20 if ext == ".bvh" else SAMPLE_BYTES)
        if ext == ".npy":
            with open(path, "rb") as handle:
                shape = _npy_header(handle)[0]
            return int(shape[0]) if len(shape) == 3 else 1
        if ext == ".npz":
            with zipfile.ZipFile(path) as archive:
                names = archive.namelist()
                name = "keypoints.npy" if "keypoints.npy" in names else names[0]
                with archive.open(name) as handle:
                    shape = _npy_header(handle)[0]
            return int(shape[0]) if len(shape) == 3 else 1
    except (OSError, ValueError, EOFError, IndexError, zipfile.BadZipFile):
        return 0
    if ext == ".bvh":
        found = re.search(rb"Frames:\s*(\d+)", head)
        return int(found.group(1)) if found else 0
    if ext == ".json":
        marks = head.count(b'"x"')
        return round(size * marks / len(head) / (joints or 1)) if head else 0
    lines = head.split(b"\n")
    if len(head) == size:  # the whole file: its rows counted
        rows = sum(1 for line in lines[1:] if line.strip())
    else:  # the last line of the head is cut short
        body = lines[1:-1]
        mean = sum(len(line) + 1 for line in body) / len(body) if body else 0
        rows = round((size - len(lines[0]) - 1) / mean) if mean else 0
    long = "joint" in _header_names(head)
    return round(rows / joints) if long and joints else rows


def _encoding(path: str | os.PathLike, what: str) -> str:
    """How the CSV is decoded: UTF-16 with its byte-order mark, else UTF-8; its head is checked
    as the whole-file reader checks all of it (a binary file is refused by its first bytes)."""
    head = _head(path)
    if len(head) == SAMPLE_BYTES:  # cut at its last line, not inside a character
        head = head[: head.rfind(b"\n") + 1] or head
    try:
        decode_text(head, what)
    except InputError as exc:
        raise KeypointFileError(str(exc)) from None
    return "utf-16" if head.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)) \
        else "utf-8-sig"


def wide_csv_parts(path: str | os.PathLike, fmt: KeypointFormat, what: str, scale: float,
                   frames: int) -> Iterator[Part]:
    """The frames of a wide keypoint CSV, ``frames`` at a time, each part as
    :func:`~.readers.read_keypoints` reads its rows (``scale``: file units a metre). A repeated
    frame number is not refused here: it may be in another part (the caller checks)."""
    encoding = _encoding(path, what)
    columns = [f"{joint}_{axis}" for joint in fmt.joints for axis in "xyz"]
    first = 1
    try:
        with open(path, encoding=encoding, newline="") as handle:
            check_header(handle.readline(), what)
            handle.seek(0)
            for table in pd.read_csv(handle, dtype=str, keep_default_na=False,
                                     skipinitialspace=True, chunksize=frames):
                table.columns = [str(c).strip() for c in table.columns]
                if first == 1:
                    absent = [c for c in columns if c not in table.columns]
                    if absent:
                        raise KeypointFileError(
                            f"{what} has no column '{absent[0]}' ({len(absent)} of format "
                            f"{fmt.name}'s {len(columns)} columns are absent; a wide keypoint "
                            "CSV has <joint>_x, <joint>_y, <joint>_z for each of its joints, a "
                            "long one the columns frame, joint, x, y, z)")
                if table.empty:
                    continue
                rows = np.arange(first, first + len(table))
                numbers = frame_numbers(table, what, first) if "frame" in table.columns \
                    else rows
                points = cell_values(table, columns, what, rows).reshape(len(table), -1, 3)
                yield Part(numbers, whole_points(points) / scale)
                first += len(table)
    except InputError as exc:  # the header's: one line naming the file, as the reader's
        raise KeypointFileError(str(exc)) from None
    except pd.errors.EmptyDataError:
        raise KeypointFileError(f"{what} is empty (expected a header row and at least one "
                                "row)") from None
    except pd.errors.ParserError as exc:
        detail = str(exc).strip().splitlines()[-1]
        raise KeypointFileError(f"{what} is not a well-formed CSV: {detail}") from None
    except UnicodeDecodeError as exc:
        raise KeypointFileError(f"{what} is not {encoding.upper()[:6]} text beyond its head "
                                f"({exc.reason}): expected a CSV file saved as UTF-8") from None
    if first == 1:
        raise KeypointFileError(f"{what} has a header but no rows")


def npy_parts(path: str | os.PathLike, scale: float, frames: int) -> Iterator[Part]:
    """The frames of an .npy file that :func:`streamed` accepts, ``frames`` at a time, each
    part as :func:`~.readers.read_keypoints` reads it."""
    layout = npy_layout(path)
    assert layout is not None, "npy_parts reads only the files streamed() accepts"
    shape, dtype, offset = layout
    per_frame = int(np.prod(shape[1:]))
    with open(path, "rb") as handle:
        handle.seek(offset)
        for start in range(0, shape[0], frames):
            count = min(frames, shape[0] - start)
            values = np.fromfile(handle, dtype=dtype, count=count * per_frame)
            points = values.reshape(count, *shape[1:]).astype(np.float64)
            yield Part(np.arange(start + 1, start + count + 1), whole_points(points) / scale)
