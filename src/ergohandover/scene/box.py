"""URDF of the handover box with its two side handles, generated from a :class:`TaskSpec`.

The box frame is the box centre with axes aligned to PyBullet's world when the box is level
and facing the worker: x toward the robot (the worker's forward), y to the worker's left,
z up. Links, all named for the worker's sides:

- ``box`` (base): the box body, ``box_depth`` x ``box_width`` x ``box_height``;
- ``left_handle``/``right_handle``: a rail along x, ``handle_span / 2`` to each side at the box
  centre's height, held off the side face by two brackets. It runs from near the box's front
  face (toward the worker) to :data:`RAIL_OVERHANG` beyond its back face (toward the robot):
  the worker grips it at the middle, the robot holds the overhang;
- ``left_grip``/``right_grip`` (massless): where the worker's power grip is centred, exactly
  :meth:`TaskSpec.handles`;
- ``left_robot_grasp``/``right_robot_grasp`` (massless): where the robot's fingers close,
  :func:`robot_grasp_offset` along the rail toward the robot, on the overhang, clear of the
  worker's hand (whose fingers, in the twin, point along the rail).

The text is a pure function of the task (fixed number formatting), so a cached file whose name
carries a hash of the text can be reused.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path
from typing import Any, NamedTuple

from ..errors import ModelError
from ..io.atomic import atomic_write
from ..twin.task import TaskSpec

HANDLE_RADIUS = 0.012  # a moulded rail a gloved hand closes around [m]
FRONT_FRACTION = 0.8  # the rail starts this fraction of the half depth in front of the centre
RAIL_OVERHANG = 0.07  # the rail runs this far beyond the box's back face [m]
GRASP_BEYOND_FACE = 0.04  # the robot's fingers close this far beyond the back face [m]
BRACKET = 0.015  # bracket edge, along x and z [m]
CARDBOARD = (0.72, 0.55, 0.33, 1.0)
HANDLE_RGBA = (0.15, 0.15, 0.15, 1.0)
SIDES = {"left": 1.0, "right": -1.0}  # the worker's left is +y in the box frame


def _num(x: float) -> str:
    return f"{float(x) + 0.0:.9g}"


def _vec(values) -> str:
    return " ".join(_num(v) for v in values)


def rail_ends(task: TaskSpec) -> tuple[float, float]:
    """Front and back end of each handle rail along x, from the box centre [m]."""
    return -FRONT_FRACTION * task.box_depth / 2.0, task.box_depth / 2.0 + RAIL_OVERHANG


def robot_grasp_offset(task: TaskSpec) -> float:
    """Distance from the worker's grip to the robot's grasp along the rail, toward the robot [m].

    The twin's hand is a paddle whose fingers point along the rail, up to 0.12 m past the grip
    (50th-percentile man); grasping 0.04 m beyond the box's back face (0.19 m for the default
    0.30 m-deep box) keeps the Panda's fingers about 5 cm clear of it.
    """
    return task.box_depth / 2.0 + GRASP_BEYOND_FACE


def _box_link(name: str, size, xyz, rgba, mass: float) -> list[str]:
    """A link with one box shape (visual and collision) and its solid inertia."""
    sx, sy, sz = size
    ixx, iyy, izz = (mass / 12.0 * (b * b + c * c) for b, c in ((sy, sz), (sx, sz), (sx, sy)))
    geometry = f'<geometry><box size="{_vec(size)}"/></geometry>'
    origin = f'<origin xyz="{_vec(xyz)}" rpy="0 0 0"/>'
    return [
        f'  <link name="{name}">',
        f'    <inertial>{origin}<mass value="{_num(mass)}"/>'
        f'<inertia ixx="{_num(ixx)}" ixy="0" ixz="0" iyy="{_num(iyy)}" iyz="0" '
        f'izz="{_num(izz)}"/></inertial>',
        f'    <visual>{origin}{geometry}<material name="{name}"><color rgba="{_vec(rgba)}"/>'
        "</material></visual>",
        f"    <collision>{origin}{geometry}</collision>",
        "  </link>",
    ]


def _handle_link(task: TaskSpec, side: str, mass: float) -> list[str]:
    """A rail along x (a cylinder turned by pitch 90°) and its two brackets to the side face:
    one at the front end, one at the back face (the overhang is cantilevered)."""
    front, back = rail_ends(task)
    sign = SIDES[side]
    gap = task.handle_span / 2.0 - task.box_width / 2.0  # side face to rail axis [m]
    rail = (f'<geometry><cylinder radius="{_num(HANDLE_RADIUS)}" length="{_num(back - front)}"/>'
            "</geometry>")
    along_x = f'<origin xyz="{_num((front + back) / 2.0)} 0 0" rpy="0 1.57079633 0"/>'
    colour = f'<material name="{side}_handle"><color rgba="{_vec(HANDLE_RGBA)}"/></material>'
    lines = [
        f'  <link name="{side}_handle">',
        f'    <inertial><origin xyz="0 0 0" rpy="0 0 0"/><mass value="{_num(mass)}"/>'
        '<inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial>',
        f"    <visual>{along_x}{rail}{colour}</visual>",
        f"    <collision>{along_x}{rail}</collision>",
    ]
    if gap > HANDLE_RADIUS:  # a rail flush with the face needs no bracket
        geometry = f'<geometry><box size="{_vec((BRACKET, gap, BRACKET))}"/></geometry>'
        for x in (front + BRACKET / 2.0, task.box_depth / 2.0 - BRACKET / 2.0):
            origin = f'<origin xyz="{_vec((x, -sign * gap / 2.0, 0.0))}" rpy="0 0 0"/>'
            lines += [f"    <visual>{origin}{geometry}{colour}</visual>",
                      f"    <collision>{origin}{geometry}</collision>"]
    return [*lines, "  </link>"]


def _frame(name: str) -> list[str]:
    """A massless, shapeless link: a named point to look up."""
    return [f'  <link name="{name}"><inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" '
            'iyy="0" iyz="0" izz="0"/></inertial></link>']


def _fixed(name: str, parent: str, child: str, xyz) -> list[str]:
    return [f'  <joint name="{name}" type="fixed"><parent link="{parent}"/><child '
            f'link="{child}"/><origin xyz="{_vec(xyz)}" rpy="0 0 0"/></joint>']


def box_urdf_text(task: TaskSpec | None = None) -> str:
    """The box's URDF as text.

    Args:
        task: box size, mass and handle span; default :class:`TaskSpec`.

    Returns:
        The URDF document, lengths [m], masses [kg]; 90% of the mass in the box body.
    """
    task = task or TaskSpec()
    size = (task.box_depth, task.box_width, task.box_height)
    lines = [
        '<?xml version="1.0"?>',
        f"<!-- Generated by ergohandover.box_urdf from {task!r}; do not edit. -->",
        '<robot name="handover_box">',
        *_box_link("box", size, (0.0, 0.0, 0.0), CARDBOARD, 0.9 * task.box_mass_kg),
    ]
    half_span, grasp = task.handle_span / 2.0, robot_grasp_offset(task)
    for side, sign in SIDES.items():
        lines += _handle_link(task, side, 0.05 * task.box_mass_kg)
        lines += _fixed(f"{side}_handle_mount", "box", f"{side}_handle",
                        (0.0, sign * half_span, 0.0))
        lines += _frame(f"{side}_grip") + _fixed(f"{side}_grip_mount", f"{side}_handle",
                                                 f"{side}_grip", (0.0, 0.0, 0.0))
        lines += _frame(f"{side}_robot_grasp") + _fixed(
            f"{side}_robot_grasp_mount", f"{side}_handle", f"{side}_robot_grasp",
            (grasp, 0.0, 0.0))
    return "\n".join([*lines, "</robot>", ""])


def cached_box_urdf(task: TaskSpec | None = None,
                    cache_dir: str | os.PathLike | None = None) -> Path:
    """A URDF file for ``task``'s box in ``cache_dir``, written only if not already there.

    Args:
        task: the box; default :class:`TaskSpec`.
        cache_dir: directory for generated files; default ``<tmp>/ergohandover_urdf``.

    Returns:
        Path of a file whose content equals ``box_urdf_text(task)``.
    """
    text = box_urdf_text(task)
    folder = Path(cache_dir) if cache_dir is not None else (
        Path(tempfile.gettempdir()) / "ergohandover_urdf")
    folder.mkdir(parents=True, exist_ok=True)
    # The hash in the name makes a stale or foreign file impossible to pick up by mistake.
    path = folder / f"box_{hashlib.sha256(text.encode()).hexdigest()[:16]}.urdf"
    if not path.is_file() or path.read_text() != text:
        atomic_write(path, lambda handle: handle.write(text))
    return path


class LoadedBox(NamedTuple):
    """A box in a PyBullet world: body id and link name -> index (base ``box`` = -1)."""

    body_id: int
    links: dict[str, int]


def load_box(client: int, task: TaskSpec | None = None,
             cache_dir: str | os.PathLike | None = None) -> LoadedBox:
    """Load the box (fixed base: it is moved kinematically, never simulated).

    Args:
        client: a PyBullet client id.
        task: the box; default :class:`TaskSpec`.
        cache_dir: where the URDF is written or reused (see :func:`cached_box_urdf`).

    Returns:
        The body id and its links, looked up by name.
    """
    from ..sim import pybullet

    p = pybullet()
    path = cached_box_urdf(task, cache_dir)
    body = p.loadURDF(str(path), useFixedBase=True, physicsClientId=client)
    if body < 0:
        raise ModelError(f"PyBullet could not load {path}")
    links: dict[str, Any] = {"box": -1}
    for i in range(p.getNumJoints(body, physicsClientId=client)):
        links[p.getJointInfo(body, i, physicsClientId=client)[12].decode()] = i
    return LoadedBox(body, links)
