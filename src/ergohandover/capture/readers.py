"""Keypoint files -> one :class:`Keypoints` record, and the checks a command runs before scoring.

A format (:mod:`~ergohandover.capture.formats`) says which joints a file holds and in what order;
the file's extension says how they are written:

- ``.csv``, wide: one row per frame, columns ``<joint>_x``, ``<joint>_y``, ``<joint>_z`` for
  every joint of the format and an optional ``frame`` column (other columns are ignored);
- ``.csv``, long (it has a ``joint`` column): columns ``frame, joint, x, y, z``, one row per
  point, the joint by name or by 0-based index; a joint a frame does not list is missing;
- ``.npy``: an array (frames, joints, 3) or (joints, 3); ``.npz``: the same under the key
  ``keypoints``, or the file's only array;
- ``.json``: MediaPipe Pose's world landmarks, a list of frames, each a list of landmark objects
  ``{"x", "y", "z", "visibility"}`` or an object holding them under ``pose_world_landmarks``,
  ``worldLandmarks`` or ``world_landmarks`` (directly, as ``{"landmark": [...]}`` as protobuf
  writes it, or as a list of poses of which the first is read).

An empty cell, a NaN, a landmark less visible than ``min_visibility`` or a frame without
landmarks is a missing point (NaN); what a missing point means for the scores is the command's
choice (:func:`check_keypoints`). Every problem is a one-line :class:`KeypointFileError` naming
the file as the user typed it.
"""

from __future__ import annotations

import io
import json
import math
import os
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..io.csv_input import InputError, decode_text, read_bytes, read_csv_text
from .formats import KeypointFormat

UNITS = {"m": 1.0, "cm": 100.0, "mm": 1000.0}
"""Length unit -> how many of it make a metre."""
EXTENSIONS = (".csv", ".npy", ".npz", ".json")
"""The extensions :func:`read_keypoints` reads (BVH files: :func:`~.bvh.read_bvh`)."""
JSON_KEYS = ("pose_world_landmarks", "worldLandmarks", "world_landmarks")
"""The keys a MediaPipe JSON frame object may hold its world landmarks under."""


class KeypointFileError(InputError):
    """A keypoint or BVH file that cannot be used; the message is one line naming the file."""


@dataclass(frozen=True, eq=False)
class Keypoints:
    """The keypoints of one file.

    Attributes:
        frames: (N,) int frame numbers: the file's ``frame`` column, else 1..N.
        points: (N, J, 3) float64 positions [m] in ``fmt``'s joint order; NaN where missing.
        fmt: the format the points are in.
    """

    frames: np.ndarray
    points: np.ndarray
    fmt: KeypointFormat


def unit_scale(units: str, what: str) -> float:
    """How many ``units`` make a metre: ``m``, ``cm``, ``mm``, or a positive number, the metres
    one file unit is (a rig's own unit: CMU's is 0.0254 / 0.45); a KeypointFileError for
    anything else."""
    if units in UNITS:
        return UNITS[units]
    try:
        metres = float(units)
    except ValueError:
        metres = math.nan
    if not (math.isfinite(metres) and metres > 0):
        raise KeypointFileError(f"{what}: units {units!r} are not allowed (use "
                                f"{', '.join(UNITS)}, or the metres one unit of the file is, "
                                "e.g. 0.0254 for inches)")
    return 1.0 / metres


def read_file_bytes(path: str, what: str, kind: str) -> bytes:
    """The bytes of ``path``; a one-line KeypointFileError if it cannot be read."""
    try:
        return read_bytes(path, what, kind)
    except InputError as exc:
        raise KeypointFileError(str(exc)) from None


def file_text(data: bytes, what: str, kind: str) -> str:
    """``data`` as UTF-8 text; a one-line KeypointFileError naming ``kind`` if it is not."""
    try:
        return decode_text(data, what, kind)
    except InputError as exc:
        raise KeypointFileError(str(exc)) from None


def read_keypoints(path: str | os.PathLike, fmt: KeypointFormat, units: str = "m",
                   min_visibility: float = 0.5) -> Keypoints:
    """Read a keypoint file (the kind by its extension; the module's text lists them).

    Args:
        path: the file, as the user typed it (messages name it so).
        fmt: the format of its joints.
        units: the file's length unit, ``m``, ``cm`` or ``mm``.
        min_visibility: a MediaPipe landmark less visible than this is missing.

    Returns:
        The file's frames and points [m].

    Raises:
        KeypointFileError: one line naming the file and what is wrong.
    """
    what = str(path)
    scale = unit_scale(units, what)
    ext = Path(what).suffix.lower()
    if ext not in EXTENSIONS:
        shown = f"extension '{ext}'" if ext else "no extension"
        hint = " (a BVH file brings its own joints: --format bvh)" if ext == ".bvh" else ""
        raise KeypointFileError(f"{what} has {shown}: a keypoint file is "
                                f"{', '.join(EXTENSIONS)}{hint}")
    kind = {".csv": "a CSV file", ".npy": "a NumPy .npy file", ".npz": "a NumPy .npz file",
            ".json": "a MediaPipe JSON file"}[ext]
    data = read_file_bytes(what, what, kind)
    if ext == ".csv":
        frames, points = _read_csv(data, fmt, what)
    elif ext in (".npy", ".npz"):
        points = _points_array(_load_numpy(data, ext, what), fmt, what)
        frames = np.arange(1, len(points) + 1)
    else:
        points = _read_json(data, fmt, what, min_visibility)
        frames = np.arange(1, len(points) + 1)
    return Keypoints(np.asarray(frames, dtype=np.int64), points / scale, fmt)


# -- CSV ---------------------------------------------------------------------------------------


def _read_csv(data: bytes, fmt: KeypointFormat, what: str) -> tuple[np.ndarray, np.ndarray]:
    text = file_text(data, what, "CSV")
    try:
        table = read_csv_text(io.StringIO(text), what)
    except InputError as exc:
        raise KeypointFileError(str(exc)) from None
    if "joint" in table.columns:
        return _read_long(table, fmt, what)
    return _read_wide(table, fmt, what)


def cell_values(table: pd.DataFrame, columns: list[str], what: str,
           row_numbers: np.ndarray | None = None) -> np.ndarray:
    """(rows, len(columns)) floats of text cells: empty (or ``nan``) is NaN; other text that is
    not a number is an error naming its row (1-based, after the header) and column."""
    text = table[columns].to_numpy(dtype=str)
    flat = pd.Series(text.ravel()).str.strip()
    values = pd.to_numeric(flat, errors="coerce").to_numpy(dtype=np.float64)
    bad = np.flatnonzero(np.isnan(values) & (flat != "").to_numpy()
                         & (flat.str.lower() != "nan").to_numpy())
    if bad.size:
        row, col = divmod(int(bad[0]), len(columns))
        row = int(row_numbers[row]) if row_numbers is not None else row + 1
        raise KeypointFileError(f"{what}: row {row}, column '{columns[col]}': "
                                f"{flat.iloc[bad[0]]!r} is not a number (expected a coordinate, "
                                f"or an empty cell for a missing point)")
    return values.reshape(text.shape)


def frame_numbers(table: pd.DataFrame, what: str, first_row: int = 1) -> np.ndarray:
    """The ``frame`` column as integers; a cell that is not a whole number is an error naming
    its row (``first_row``: the number of the table's first row, for a part of a file)."""
    text = table["frame"].str.strip()
    values = pd.to_numeric(text, errors="coerce").to_numpy(dtype=np.float64)
    bad = np.flatnonzero(~np.isfinite(values) | (values != np.round(values)))
    if bad.size:
        cell = text.iloc[bad[0]]
        shown = repr(cell) if cell else "an empty cell"
        raise KeypointFileError(f"{what}: row {bad[0] + first_row}, column 'frame': {shown} "
                                "is not a frame number (expected a whole number)")
    return values.astype(np.int64)


def whole_points(points: np.ndarray) -> np.ndarray:
    """A point with any coordinate missing is missing as a whole."""
    return np.where(np.isnan(points).any(axis=-1, keepdims=True), np.nan, points)


def _read_wide(table: pd.DataFrame, fmt: KeypointFormat,
               what: str) -> tuple[np.ndarray, np.ndarray]:
    columns = [f"{joint}_{axis}" for joint in fmt.joints for axis in "xyz"]
    absent = [c for c in columns if c not in table.columns]
    if absent:
        raise KeypointFileError(
            f"{what} has no column '{absent[0]}' ({len(absent)} of format {fmt.name}'s "
            f"{len(columns)} columns are absent; a wide keypoint CSV has <joint>_x, <joint>_y, "
            f"<joint>_z for each of its joints, a long one the columns frame, joint, x, y, z)")
    if "frame" in table.columns:
        frames = frame_numbers(table, what)
        repeated_frame(frames, what)
    else:
        frames = np.arange(1, len(table) + 1)
    points = cell_values(table, columns, what).reshape(len(table), len(fmt.joints), 3)
    return frames, whole_points(points)


def repeated_frame(frames: np.ndarray, what: str) -> None:
    """Refuse a frame number in two rows (a file read whole, or every part's frames)."""
    order = np.argsort(frames, kind="stable")
    same = np.flatnonzero(np.diff(frames[order]) == 0)
    if same.size:
        first, second = sorted((int(order[same[0]]), int(order[same[0] + 1])))
        raise KeypointFileError(f"{what}: frame {frames[first]} is in rows {first + 1} and "
                                f"{second + 1} (expected one row per frame)")


def _read_long(table: pd.DataFrame, fmt: KeypointFormat,
               what: str) -> tuple[np.ndarray, np.ndarray]:
    required = ("frame", "joint", "x", "y", "z")
    absent = [c for c in required if c not in table.columns]
    if absent:
        raise KeypointFileError(f"{what} has a 'joint' column but no column '{absent[0]}' "
                                f"(a long keypoint CSV has the columns {', '.join(required)})")
    frames = frame_numbers(table, what)
    joint = _joint_indices(table["joint"].str.strip(), frames, fmt, what)
    xyz = cell_values(table, ["x", "y", "z"], what)
    numbers, row_frame = np.unique(frames, return_inverse=True)
    key = row_frame * len(fmt.joints) + joint
    order = np.argsort(key, kind="stable")
    same = np.flatnonzero(np.diff(key[order]) == 0)
    if same.size:
        first, second = int(order[same[0]]), int(order[same[0] + 1])
        raise KeypointFileError(
            f"{what}: frame {frames[first]} lists joint '{fmt.joints[joint[first]]}' twice "
            f"(rows {first + 1} and {second + 1}; expected each joint at most once a frame)")
    points = np.full((len(numbers), len(fmt.joints), 3), np.nan)
    points[row_frame, joint] = xyz
    return numbers, whole_points(points)


def _joint_indices(names: pd.Series, frames: np.ndarray, fmt: KeypointFormat,
                   what: str) -> np.ndarray:
    """Each row's joint index, from a name of the format or a 0-based index."""
    count = len(fmt.joints)
    by_name = names.map(pd.Series(np.arange(count), index=list(fmt.joints)))
    by_name = by_name.to_numpy(dtype=np.float64)
    numeric = pd.to_numeric(names, errors="coerce").to_numpy(dtype=np.float64, copy=True)
    numeric[~np.isfinite(numeric) | (numeric != np.round(numeric)) | ~np.isnan(by_name)] = np.nan
    beyond = np.flatnonzero(numeric >= count)
    if beyond.size:
        row = int(beyond[np.argmax(numeric[beyond])])
        raise KeypointFileError(
            f"{what}: frame {frames[row]} has joint index {int(numeric[row])} (so at least "
            f"{int(numeric[row]) + 1} joints); format {fmt.name} has {count} (indices "
            f"0-{count - 1}; row {row + 1})")
    index = np.where(np.isnan(by_name), numeric, by_name)
    bad = np.flatnonzero(np.isnan(index) | (index < 0))
    if bad.size:
        row = int(bad[0])
        shown = repr(names.iloc[row]) if names.iloc[row] else "an empty cell"
        raise KeypointFileError(
            f"{what}: row {row + 1}, column 'joint': {shown} is not a joint of format "
            f"{fmt.name} (use its joint names, e.g. {fmt.joints[0]}, or indices 0-{count - 1})")
    return index.astype(np.int64)


# -- NumPy -------------------------------------------------------------------------------------


def _load_numpy(data: bytes, ext: str, what: str) -> np.ndarray:
    """The array of an ``.npy`` file, or the keypoints of an ``.npz`` one."""
    try:
        if ext == ".npy":
            if not data.startswith(b"\x93NUMPY"):
                raise KeypointFileError(f"{what} is not a NumPy .npy file (it does not start "
                                        f"with the .npy header)")
            return np.load(io.BytesIO(data), allow_pickle=False)
        if not data.startswith(b"PK"):
            raise KeypointFileError(f"{what} is not a NumPy .npz file (not a zip archive)")
        with np.load(io.BytesIO(data), allow_pickle=False) as archive:
            keys = list(archive.files)
            if "keypoints" in keys:
                return archive["keypoints"]
            if len(keys) == 1:
                return archive[keys[0]]
            if not keys:
                raise KeypointFileError(f"{what} holds no arrays (expected the keypoints as "
                                        f"(frames, joints, 3))")
            raise KeypointFileError(
                f"{what} holds {len(keys)} arrays ({', '.join(keys)}) and none is called "
                f"'keypoints': expected one array, or the keypoints under the key 'keypoints'")
    except KeypointFileError:
        raise
    except (ValueError, OSError, EOFError, zipfile.BadZipFile) as exc:
        detail = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise KeypointFileError(f"{what} cannot be read as a NumPy {ext} file: {detail}") \
            from None


def _points_array(array: np.ndarray, fmt: KeypointFormat, what: str) -> np.ndarray:
    """(N, J, 3) float64 from an (N, J, 3) or (J, 3) numeric array of ``fmt``'s joints."""
    count = len(fmt.joints)
    if array.dtype.kind not in "fiu":
        raise KeypointFileError(f"{what} holds an array of {array.dtype} values (expected "
                                f"numbers: the keypoints as (frames, {count}, 3))")
    if array.ndim == 2:
        array = array[None]
    if array.ndim != 3 or array.shape[2] != 3:
        raise KeypointFileError(f"{what} holds an array of shape {tuple(array.shape)} "
                                f"(expected (frames, {count}, 3), or ({count}, 3) for one "
                                f"frame, for format {fmt.name})")
    if array.shape[1] != count:
        raise KeypointFileError(
            f"{what}: every frame has {array.shape[1]} joints; format {fmt.name} has {count} "
            f"(the array's shape is {tuple(array.shape)}; expected (frames, {count}, 3))")
    return whole_points(array.astype(np.float64))


# -- MediaPipe JSON ----------------------------------------------------------------------------


def _kind(value) -> str:
    """What a JSON value is, for messages."""
    if value is None:
        return "null"
    return {bool: "true/false", int: "a number", float: "a number", str: "a string",
            list: "a list", dict: "an object"}.get(type(value), type(value).__name__)


def _read_json(data: bytes, fmt: KeypointFormat, what: str,
               min_visibility: float) -> np.ndarray:
    text = file_text(data, what, "JSON")
    try:
        document = json.loads(text)
    except json.JSONDecodeError as exc:
        raise KeypointFileError(f"{what} is not valid JSON: {exc.msg} (line {exc.lineno}, "
                                f"column {exc.colno})") from None
    if isinstance(document, dict):
        frames = [document]
    elif isinstance(document, list) and document and isinstance(document[0], dict) \
            and "x" in document[0]:
        frames = [document]  # one frame: a list of landmark objects
    elif isinstance(document, list):
        frames = document
    else:
        raise KeypointFileError(
            f"{what} holds {_kind(document)}: expected a list of frames (each a list of "
            f"MediaPipe world landmarks or an object with {', '.join(JSON_KEYS)})")
    count = len(fmt.joints)
    points = np.full((len(frames), count, 3), np.nan)
    for i, frame in enumerate(frames):
        landmarks = _frame_landmarks(frame, i + 1, what)
        if not landmarks:
            continue
        if len(landmarks) != count:
            raise KeypointFileError(
                f"{what}: frame {i + 1} has {len(landmarks)} joints; format {fmt.name} has "
                f"{count} (expected a list of {count} landmarks a frame)")
        for j, mark in enumerate(landmarks):
            points[i, j] = _landmark(mark, i + 1, fmt.joints[j], j, what, min_visibility)
    return whole_points(points)


def _frame_landmarks(frame, number: int, what: str) -> list:
    """A frame's landmark objects (empty for a frame without a pose)."""
    if isinstance(frame, dict):
        key = next((k for k in (*JSON_KEYS, "landmark") if k in frame), None)
        if key is None:
            keys = ", ".join(list(frame)[:6]) or "none"
            raise KeypointFileError(
                f"{what}: frame {number} is an object without {', '.join(JSON_KEYS)} (its "
                f"keys: {keys})")
        frame = frame[key]
        if isinstance(frame, dict) and "landmark" in frame:
            frame = frame["landmark"]  # protobuf's NormalizedLandmarkList as JSON
        elif isinstance(frame, list) and frame and isinstance(frame[0], list):
            frame = frame[0]  # a list of poses (the Tasks API): the first
        elif isinstance(frame, list) and frame and isinstance(frame[0], dict) \
                and "landmark" in frame[0]:
            frame = frame[0]["landmark"]  # a list of protobuf poses: the first
    if frame is None:
        return []
    if not isinstance(frame, list):
        raise KeypointFileError(
            f"{what}: frame {number} is {_kind(frame)}: expected a list of landmark objects "
            f"with x, y, z (or an object with {', '.join(JSON_KEYS)})")
    return frame


def _landmark(mark, frame: int, joint: str, index: int, what: str,
              min_visibility: float) -> tuple[float, float, float]:
    """One landmark's (x, y, z); NaN if it is less visible than ``min_visibility``."""
    where = f"{what}: frame {frame}, landmark {index} ({joint})"
    if not isinstance(mark, dict):
        raise KeypointFileError(f"{where} is {_kind(mark)}: expected an object with x, y, z "
                                f"and an optional visibility")
    values = []
    for key in ("x", "y", "z", "visibility"):
        if key not in mark and key != "visibility":
            raise KeypointFileError(f"{where} has no '{key}' (expected an object with x, y, z "
                                    f"and an optional visibility)")
        value = mark.get(key)
        if value is None:  # a null coordinate is a missing point; no visibility is seen
            values.append(np.nan if key != "visibility" else np.inf)
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise KeypointFileError(f"{where}: '{key}' is {_kind(value)} (expected a number)")
        values.append(float(value))
    if values[3] < min_visibility:
        return (np.nan, np.nan, np.nan)
    return (values[0], values[1], values[2])
