"""BVH motion files: a small reader (hierarchy, motion, forward kinematics over all frames at
once), without a dependency beyond numpy (the writer: :mod:`.bvh_write`).

A BVH file brings its own joints, so :func:`read_bvh` builds the keypoint format from the file:
its joints and End Sites (``<parent>_End``) in file order, y up (BVH's convention; a file in
another frame takes ``--up``), and the landmarks of the rig its names fit best (:mod:`.rigs`:
Xsens MVN, CMU, Mixamo, Rokoko, OptiTrack Motive, Perception Neuron, Blender Rigify), each from
a joint that does not sit on the landmark it is measured against; ``--joint-map`` names the
landmarks of any other rig.

Rotations: a joint's local rotation is the product of its rotation channels in the order the
file lists them (intrinsic: ``R = R_first @ R_second @ R_third``), in degrees; its frame is its
parent's turned by that rotation and moved by its OFFSET plus any position channels, unless
those restate the OFFSETs (:func:`_restated`).
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd

from .formats import KeypointFormat
from .readers import KeypointFileError, Keypoints, file_text, read_file_bytes, unit_scale
from .rigs import RIGS, recognise, resolve

REQUIRED = tuple(f"{side}_{part}" for part in ("hip", "knee", "ankle", "shoulder", "elbow",
                                               "wrist") for side in ("left", "right"))
"""The landmarks a BVH file must give."""
CHANNELS = ("Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation")


def axis_rotation(axis: int, degrees: np.ndarray) -> np.ndarray:
    """(..., 3, 3) rotations by ``degrees`` about coordinate axis ``axis`` (0 = x)."""
    a = np.radians(np.asarray(degrees, dtype=np.float64))
    c, s = np.cos(a), np.sin(a)
    out = np.zeros((*a.shape, 3, 3))
    i, j, k = axis, (axis + 1) % 3, (axis + 2) % 3
    out[..., i, i] = 1.0
    out[..., j, j], out[..., j, k] = c, -s
    out[..., k, j], out[..., k, k] = s, c
    return out


@dataclass
class _Node:
    name: str
    parent: int
    line: int
    end_site: bool = False
    offset: tuple[float, float, float] | None = None
    channels: tuple[str, ...] = ()


def _fail(what: str, line: int, message: str) -> KeypointFileError:
    return KeypointFileError(f"{what}: line {line}: {message}")


def _numbers(tokens: list[str], what: str, line: int, field: str) -> list[float]:
    try:
        return [float(t) for t in tokens]
    except ValueError:
        bad = next(t for t in tokens if not _is_number(t))
        raise _fail(what, line, f"{field} value {bad!r} is not a number") from None


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def _parse_hierarchy(lines: list[str], what: str) -> tuple[list[_Node], int]:
    """The joints and End Sites in file order, and the index of the MOTION line."""
    first = next((i for i, line in enumerate(lines) if line.strip()), None)
    if first is None or lines[first].split()[0].upper() != "HIERARCHY":
        shown = "an empty file" if first is None else f"line {first + 1} is " \
            f"{lines[first].strip()[:40]!r}"
        raise KeypointFileError(f"{what} is not a BVH file: it does not start with HIERARCHY "
                                f"({shown})")
    nodes: list[_Node] = []
    stack: list[int] = []
    expect_brace = False
    motion = None
    for number in range(first + 1, len(lines)):
        words = lines[number].split()
        line = number + 1
        if not words:
            continue
        if words[0].upper() == "MOTION":
            motion = number
            break
        while words:
            word, rest = words[0], words[1:]
            if expect_brace and word != "{":
                raise _fail(what, line, f"expected '{{' after {nodes[-1].name}, found {word!r}")
            if word == "{":
                expect_brace = False
                stack.append(len(nodes) - 1)
                words = rest
            elif word == "}":
                if not stack:
                    raise _fail(what, line, "a '}' closes no joint")
                top = nodes[stack.pop()]
                if top.offset is None:
                    raise _fail(what, line, f"{top.name} has no OFFSET")
                words = rest
            elif word in ("ROOT", "JOINT"):
                if not rest:
                    raise _fail(what, line, f"{word} without a name")
                if word == "JOINT" and not stack:
                    raise _fail(what, line, f"JOINT {rest[0]} outside a ROOT")
                if stack and nodes[stack[-1]].end_site:
                    raise _fail(what, line, f"{word} {rest[0]} inside an End Site")
                if word == "ROOT" and stack:
                    raise _fail(what, line, f"ROOT {rest[0]} inside joint "
                                f"{nodes[stack[-1]].name}")
                name = rest[0].split(":")[-1]  # mixamorig:Hips -> Hips
                nodes.append(_Node(name, stack[-1] if stack else -1, line))
                expect_brace = True
                words = rest[1:]
            elif word == "End":
                if not rest or rest[0] != "Site":
                    raise _fail(what, line, "expected 'End Site'")
                if not stack or nodes[stack[-1]].end_site:
                    raise _fail(what, line, "an End Site outside a joint")
                nodes.append(_Node(f"{nodes[stack[-1]].name}_End", stack[-1], line, True))
                expect_brace = True
                words = rest[1:]
            elif word == "OFFSET":
                if not stack:
                    raise _fail(what, line, "an OFFSET outside a joint")
                if len(rest) != 3:
                    raise _fail(what, line, f"OFFSET has {len(rest)} values (expected 3)")
                x, y, z = _numbers(rest, what, line, "OFFSET")
                nodes[stack[-1]].offset = (x, y, z)
                words = []
            elif word == "CHANNELS":
                node = nodes[stack[-1]] if stack else None
                if node is None or node.end_site:
                    raise _fail(what, line, "CHANNELS outside a joint")
                if not rest or not rest[0].isdigit():
                    raise _fail(what, line, "CHANNELS without a count")
                count, names = int(rest[0]), rest[1:]
                if count != len(names):
                    raise _fail(what, line, f"CHANNELS {count} lists {len(names)} channel(s) "
                                f"({' '.join(names) or 'none'})")
                unknown = [n for n in names if n not in CHANNELS]
                if unknown:
                    raise _fail(what, line, f"channel {unknown[0]!r} is not known (use "
                                f"{', '.join(CHANNELS)})")
                if len(set(names)) != len(names):
                    raise _fail(what, line, f"CHANNELS repeats a channel ({' '.join(names)})")
                node.channels = tuple(names)
                words = []
            else:
                raise _fail(what, line, f"unexpected {word!r} in the HIERARCHY (expected ROOT, "
                            f"JOINT, End Site, OFFSET, CHANNELS or braces)")
    if not nodes:
        raise KeypointFileError(f"{what}: the HIERARCHY has no ROOT")
    if stack or expect_brace:
        raise KeypointFileError(f"{what}: the HIERARCHY ends with {nodes[stack[-1]].name} "
                                f"still open (a '}}' is missing)" if stack else
                                f"{what}: {nodes[-1].name} has no '{{'")
    if motion is None:
        raise KeypointFileError(f"{what} has no MOTION section after its HIERARCHY")
    _name_end_sites(nodes, what)
    return nodes, motion


def _name_end_sites(nodes: list[_Node], what: str) -> None:
    """Unique names: a second End Site of a joint is ``<parent>_End2``; repeated joint names
    are an error."""
    seen: dict[str, int] = {}
    for node in nodes:
        if node.end_site:
            base, k = node.name, 2
            while node.name in seen:
                node.name, k = f"{base}{k}", k + 1
        if node.name in seen:
            raise KeypointFileError(f"{what}: joint name {node.name!r} is on lines "
                                    f"{seen[node.name]} and {node.line} (expected unique names)")
        seen[node.name] = node.line


def _header_value(lines: list[str], index: int, label: str, what: str) -> tuple[str, int]:
    """The value after ``label`` on the first non-empty line from ``index``."""
    while index < len(lines) and not lines[index].strip():
        index += 1
    pattern = r"\s+".join(label.split())
    match = re.match(rf"\s*{pattern}:\s*(\S+)\s*$", lines[index]) if index < len(lines) \
        else None
    if match is None:
        line = min(index, len(lines) - 1) + 1
        raise _fail(what, line, f"expected '{label}: <value>' in the MOTION section")
    return match.group(1), index


def _parse_motion(lines: list[str], motion: int, channels: int,
                  what: str) -> tuple[np.ndarray, float]:
    """(frames, channels) values of the MOTION section starting at line index ``motion``, and
    its frame time [s]."""
    text, at = _header_value(lines, motion + 1, "Frames", what)
    if not text.isdigit():
        raise _fail(what, at + 1, f"'Frames: {text}' is not a whole number of frames")
    frames = int(text)
    text, at = _header_value(lines, at + 1, "Frame Time", what)
    if not _is_number(text) or not float(text) > 0:
        raise _fail(what, at + 1, f"'Frame Time: {text}' is not a positive number of seconds")
    frame_time = float(text)
    rows = [(i + 1, line) for i, line in enumerate(lines[at + 1:], start=at + 1)
            if line.strip()]
    counts = np.array([len(line.split()) for _, line in rows], dtype=np.int64)
    wrong = np.flatnonzero(counts != channels)
    if wrong.size:
        k = int(wrong[0])
        raise _fail(what, rows[k][0], f"frame {k + 1} has {counts[k]} values; the HIERARCHY "
                    f"has {channels} channels")
    if len(rows) != frames:
        raise KeypointFileError(f"{what}: 'Frames: {frames}' but the MOTION section has "
                                f"{len(rows)} frame rows")
    tokens = " ".join(line for _, line in rows).split()
    try:
        values = np.array(tokens, dtype=np.float64)
    except ValueError:
        parsed = pd.to_numeric(pd.Series(tokens), errors="coerce").to_numpy()
        bad = int(np.flatnonzero(np.isnan(parsed) & (pd.Series(tokens).str.lower() != "nan")
                                 .to_numpy())[0])
        k = bad // channels
        raise _fail(what, rows[k][0], f"frame {k + 1}: {tokens[bad]!r} is not a number") \
            from None
    return values.reshape(frames, channels), frame_time


def _forward(nodes: list[_Node], motion: np.ndarray) -> np.ndarray:
    """(frames, nodes, 3) positions of every joint and End Site, in the file's unit."""
    n = len(motion)
    pos = np.zeros((len(nodes), n, 3))
    rot = np.zeros((len(nodes), n, 3, 3))
    column = 0
    restated = _restated(nodes, motion)
    for j, node in enumerate(nodes):
        move = np.broadcast_to(np.asarray(node.offset, dtype=np.float64), (n, 3)).copy()
        turn = np.broadcast_to(np.eye(3), (n, 3, 3))
        for channel in node.channels:
            axis = "XYZ".index(channel[0])
            if channel.endswith("position"):
                if node.parent < 0 or not restated:
                    move[:, axis] += motion[:, column]
            else:
                turn = turn @ axis_rotation(axis, motion[:, column])
            column += 1
        if node.parent < 0:
            pos[j], rot[j] = move, turn
        else:
            parent = rot[node.parent]
            pos[j] = pos[node.parent] + np.einsum("nab,nb->na", parent, move)
            rot[j] = parent @ turn
    return pos.transpose(1, 0, 2)


def _restated(nodes: list[_Node], motion: np.ndarray) -> bool:
    """Whether the position channels below the root restate the OFFSETs (each joint's whole
    local translation, as Perception Neuron's exports "with displacement" write every joint)
    rather than move them: they lie nearer the OFFSETs than zero (median frames, summed over
    the joints). Added to the OFFSETs, restated channels would double every bone."""
    near_offset = near_zero = column = 0
    for node in nodes:
        moves = [(column + k, "XYZ".index(c[0])) for k, c in enumerate(node.channels)
                 if c.endswith("position")]
        column += len(node.channels)
        if node.parent < 0 or not moves:
            continue
        at, axes = (list(x) for x in zip(*moves, strict=True))
        offset = np.asarray(node.offset, dtype=np.float64)[axes]
        near_offset += np.median(np.linalg.norm(motion[:, at] - offset, axis=1))
        near_zero += np.median(np.linalg.norm(motion[:, at], axis=1))
    return bool(near_offset < near_zero)


class JointMapError(KeypointFileError):
    """A ``--joint-map`` entry the file cannot take (a joint it lacks); one line."""


def bvh_format(names: Sequence[str], what: str, points: np.ndarray | None = None,
               parents: Sequence[int] | None = None,
               joint_map: Mapping[str, str] | None = None) -> KeypointFormat:
    """The keypoint format of a BVH file's joints.

    Args:
        names: the joints and End Sites, in file order.
        what: the file, for messages.
        points: their (N, J, 3) positions: a landmark is not taken from a joint that sits on
            the landmark it is measured against (:func:`~.rigs.resolve`).
        parents: each one's parent's index (parents first): the body the size checks measure
            is the landmarks' joints, the joints above them and the feet below the ankles (not
            props or fingers).
        joint_map: landmark -> joint the user named (``--joint-map``), taken as given.

    Raises:
        JointMapError: a mapped joint the file lacks. KeypointFileError: a landmark of
        :data:`REQUIRED` that neither the rig nor the map gives.
    """
    joint_map = dict(joint_map or {})
    present = set(names)
    for landmark, joint in joint_map.items():
        if joint not in present:
            import difflib

            close = difflib.get_close_matches(joint, names, n=1)
            hint = f"did you mean {close[0]}? " if close else ""
            raise JointMapError(f"{what} has no joint {joint!r} for {landmark} ({hint}its "
                                f"joints: {', '.join(names)})")
    rig, fit = recognise(names)
    landmarks = resolve(rig, names, points, joint_map)
    for landmark in REQUIRED:
        if landmark in landmarks:
            continue
        words = landmark.replace("_", " ")
        if not fit:
            raise KeypointFileError(
                f"{what}: no joint for the {words}: the file's joint names fit none of the "
                f"rigs known ({', '.join(r.name for r in RIGS)}); --joint-map "
                f"{landmark}=JOINT,... names its landmarks")
        raise KeypointFileError(
            f"{what}: no joint for the {words} (looked for "
            f"{', '.join(rig.landmarks[landmark])}: the {rig.name} rig's name for it, whose "
            f"names the file's fit best; --joint-map {landmark}=JOINT names it)")
    body = set()
    for joint in set(landmarks.values()):
        at = names.index(joint)
        while at >= 0 and names[at] not in body:
            body.add(names[at])
            at = parents[at] if parents is not None else -1
    feet = {landmarks[f"{side}_ankle"] for side in ("left", "right")}
    for j, parent in enumerate(parents or ()):  # the feet below the ankles: the body's floor
        if parent >= 0 and names[parent] in feet:
            feet.add(names[j])
    body |= feet
    title = f"{rig.name} rig" if fit else "a rig of unknown names"
    if joint_map:
        title = f"{len(joint_map)} landmark(s) by --joint-map, the others by the {title}"
    return KeypointFormat("bvh", title, tuple(names), "y",
                          {m: (j,) for m, j in landmarks.items()},
                          body=tuple(n for n in names if n in body) if parents is not None
                          else ())


@dataclass(frozen=True, eq=False)
class BvhMotion:
    """A BVH file's hierarchy and the positions of its points in every frame.

    Attributes:
        names: the joints and End Sites (``<parent>_End``) in file order, namespaces stripped.
        parents: each one's parent's index (-1 for a root).
        frame_time: seconds between frames.
        points: (N, len(names), 3) positions [m] in the file's frame.
        rest: (len(names), 3) positions [m] in the rest pose (the OFFSETs, no rotation).
    """

    names: tuple[str, ...]
    parents: tuple[int, ...]
    frame_time: float
    points: np.ndarray
    rest: np.ndarray


RADIANS_AT_MOST = np.pi + 0.05
"""Rotations that all lie within ± this (and some beyond :data:`STILL_DEG`) read as radians: in
degrees, a whole take that turns no joint more than 3° is not a recording of work."""
STILL_DEG = 0.3
"""Below this largest rotation a take is still in either unit and is taken as given."""


def _rotations_in_degrees(nodes: list[_Node], motion: np.ndarray, radians: bool,
                          what: str) -> np.ndarray:
    """``motion`` with its rotation channels in degrees: converted when ``radians``; else a
    take whose every rotation reads as radians is refused in one line naming ``--radians``."""
    turns = np.array([c.endswith("rotation") for node in nodes for c in node.channels])
    if not turns.any():
        return motion
    if radians:
        motion = motion.copy()
        motion[:, turns] = np.degrees(motion[:, turns])
        return motion
    largest = float(np.abs(motion[:, turns]).max(initial=0.0))
    if STILL_DEG < largest <= RADIANS_AT_MOST:
        raise KeypointFileError(
            f"{what}: every rotation is within ±{RADIANS_AT_MOST:.2f} (the largest "
            f"{largest:.3g}): these look like radians, and BVH rotations are degrees; give "
            "--radians to read them as radians")
    return motion


def parse_bvh(path: str | os.PathLike, units: str = "m", radians: bool = False) -> BvhMotion:
    """Read a BVH file's hierarchy and motion, and run its forward kinematics.

    Args:
        path: the file, as the user typed it (messages name it so).
        units: the file's length unit, ``m``, ``cm`` or ``mm``.
        radians: its rotations are radians (BVH's are degrees; a file whose rotations read as
            radians is refused without it).

    Raises:
        KeypointFileError: one line naming the file (and the line, where it helps).
    """
    what = str(path)
    scale = unit_scale(units, what)
    text = file_text(read_file_bytes(what, what, "a BVH file"), what, "BVH")
    lines = text.splitlines()
    nodes, motion_line = _parse_hierarchy(lines, what)
    channels = sum(len(node.channels) for node in nodes)
    motion, frame_time = _parse_motion(lines, motion_line, channels, what)
    motion = _rotations_in_degrees(nodes, motion, radians, what)
    return BvhMotion(tuple(node.name for node in nodes), tuple(node.parent for node in nodes),
                     frame_time, _forward(nodes, motion) / scale,
                     _forward(nodes, np.zeros((1, channels)))[0] / scale)


def read_bvh(path: str | os.PathLike, units: str = "m",
             joint_map: Mapping[str, str] | None = None, radians: bool = False) -> Keypoints:
    """Read a BVH file as keypoints: every joint's and End Site's position in every frame.

    Args:
        path, units, radians: as :func:`parse_bvh`.
        joint_map: landmark -> joint, for a rig :mod:`.rigs` does not know (or to override it).

    Returns:
        Frames 1..N, points [m] in the file's frame (y up by BVH's convention), and the format
        of the file's joints (:func:`bvh_format`) with the rest pose, the shoulders' neutral.

    Raises:
        KeypointFileError: one line naming the file (and the line, where it helps); a file
        without a joint for one of :data:`REQUIRED` is one too, and a ``joint_map`` joint it
        lacks a :class:`JointMapError`.
    """
    motion = parse_bvh(path, units, radians)
    fmt = bvh_format(motion.names, str(path), motion.points, motion.parents, joint_map)
    fmt = replace(fmt, rest=tuple(map(tuple, motion.rest.tolist())))
    return Keypoints(np.arange(1, len(motion.points) + 1), motion.points, fmt)
