"""Writing BVH motion files, and the ZXY rotations BVH channels use: what the example files and
the round trips that check :mod:`.bvh`'s reader are made with (``R = Rz @ Rx @ Ry``)."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from .bvh import axis_rotation

ROOT_CHANNELS = ("Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation")
"""The channels :func:`bvh_text` gives a root (its other joints: the last three)."""


def zxy_matrix(angles: np.ndarray) -> np.ndarray:
    """(..., 3, 3) ``Rz @ Rx @ Ry`` from (..., 3) angles (z, x, y) [deg]."""
    angles = np.asarray(angles, dtype=np.float64)
    return (axis_rotation(2, angles[..., 0]) @ axis_rotation(0, angles[..., 1])
            @ axis_rotation(1, angles[..., 2]))


def zxy_angles(rotation: np.ndarray) -> np.ndarray:
    """(..., 3) angles (z, x, y) [deg] with ``zxy_matrix(angles) == rotation``; x in [-90, 90]
    (at ±90, where z and y turn about one axis, y is 0)."""
    r = np.asarray(rotation, dtype=np.float64)
    cos_x = np.hypot(r[..., 0, 1], r[..., 1, 1])
    x = np.arctan2(r[..., 2, 1], cos_x)
    locked = cos_x < 1e-12
    z = np.where(locked, np.arctan2(r[..., 1, 0], r[..., 0, 0]),
                 np.arctan2(-r[..., 0, 1], r[..., 1, 1]))
    y = np.where(locked, 0.0, np.arctan2(-r[..., 2, 0], r[..., 2, 2]))
    return np.degrees(np.stack([z, x, y], axis=-1))


def _number(value: float, decimals: int) -> str:
    text = f"{value:.{decimals}f}"
    return "0" if float(text) == 0 else text.rstrip("0").rstrip(".")


def bvh_text(names: Sequence[str], parents: Sequence[int], offsets: np.ndarray,
             angles: np.ndarray, root_positions: np.ndarray, frame_time: float = 1 / 30,
             end_sites: Mapping[int, Sequence[float]] | None = None,
             decimals: int = 9) -> str:
    """A BVH file's text from a hierarchy as data and per-frame local rotations.

    Args:
        names: the J joints' names; ``parents[j]`` is joint j's parent's index (-1 for a root),
            a parent listed before its children.
        offsets: (J, 3) each joint's position in its parent's frame at rest [the file's unit].
        angles: (N, J, 3) each joint's local rotation as ZXY Euler angles (z, x, y) [deg]:
            ``R = Rz @ Rx @ Ry`` (:func:`zxy_angles` turns matrices into them).
        root_positions: (N, R, 3) or (N, 3) the roots' position channels, added to their
            offsets [the file's unit].
        frame_time: seconds between frames.
        end_sites: joint index -> the offset of an End Site it ends with.
        decimals: digits after the point in every number.

    Returns:
        The text: roots with the channels ``Xposition Yposition Zposition Zrotation Xrotation
        Yrotation``, other joints ``Zrotation Xrotation Yrotation``; joints written depth
        first (children in the order given), the motion's columns in the same order.
    """
    names, parents = list(names), list(parents)
    offsets = np.asarray(offsets, dtype=np.float64).reshape(len(names), 3)
    angles = np.asarray(angles, dtype=np.float64).reshape(-1, len(names), 3)
    roots = [j for j, p in enumerate(parents) if p < 0]
    root_positions = np.asarray(root_positions, dtype=np.float64).reshape(
        len(angles), len(roots), 3)
    if any(p >= j for j, p in enumerate(parents)):
        raise ValueError("every joint's parent must be listed before it")
    end_sites = dict(end_sites or {})
    children: dict[int, list[int]] = {j: [] for j in range(len(names))}
    for j, p in enumerate(parents):
        if p >= 0:
            children[p].append(j)

    def vec(v) -> str:
        return " ".join(_number(float(x), decimals) for x in v)

    out = ["HIERARCHY"]
    order: list[int] = []

    def write(j: int, depth: int) -> None:
        pad = "  " * depth
        root = parents[j] < 0
        out.append(f"{pad}{'ROOT' if root else 'JOINT'} {names[j]}")
        out.append(f"{pad}{{")
        out.append(f"{pad}  OFFSET {vec(offsets[j])}")
        chans = ROOT_CHANNELS if root else ROOT_CHANNELS[3:]
        out.append(f"{pad}  CHANNELS {len(chans)} {' '.join(chans)}")
        order.append(j)
        for child in children[j]:
            write(child, depth + 1)
        if j in end_sites:
            out.append(f"{pad}  End Site")
            out.append(f"{pad}  {{")
            out.append(f"{pad}    OFFSET {vec(end_sites[j])}")
            out.append(f"{pad}  }}")
        out.append(f"{pad}}}")

    for root in roots:
        write(root, 0)
    columns = []
    for j in order:
        if parents[j] < 0:
            columns.append(root_positions[:, roots.index(j)])
        columns.append(angles[:, j])
    motion = np.concatenate(columns, axis=1) if columns else np.zeros((len(angles), 0))
    motion = np.round(motion, decimals) + 0.0  # no "-0"
    rows = [" ".join(f"{v:.{decimals}f}" for v in row) for row in motion.tolist()]
    out += ["MOTION", f"Frames: {len(motion)}", f"Frame Time: {frame_time:.8f}", *rows]
    return "\n".join(out) + "\n"


def write_bvh(path: str | os.PathLike, names: Sequence[str], parents: Sequence[int],
              offsets: np.ndarray, angles: np.ndarray, root_positions: np.ndarray,
              frame_time: float = 1 / 30, end_sites: Mapping[int, Sequence[float]] | None = None,
              decimals: int = 9) -> None:
    """Write :func:`bvh_text`'s text to ``path``."""
    Path(path).write_text(bvh_text(names, parents, offsets, angles, root_positions, frame_time,
                                   end_sites, decimals))
