"""URDF of the dual-arm robot, written from a :class:`~.robot.RobotSpec`.

One description holds the whole robot: a mobile base that drives toward the worker (the
prismatic ``base_drive`` joint), a stand on it, a vertical lift on the stand (the prismatic
``torso_lift`` joint, carrying a crossbar), and two Franka Panda arms bolted to the crossbar
``arm_spacing`` apart, both facing the worker. The arms are pybullet_data's
``franka_panda/panda.urdf`` (Apache-2.0), copied element by element with every link and joint
name prefixed ``left_`` or ``right_``; their meshes stay where pybullet_data installed them and
are referenced as ``package://franka_panda/meshes/...``. PyBullet does not resolve that
prefix, so :func:`cached_robot_urdf` writes a copy with the installed path in its place.

Robot frame: the origin on the floor under the middle of the crossbar with the base driven
fully back, x toward the worker, z up; the left arm (which holds the handle in the worker's
left hand) at y = -spacing/2 (the robot faces the worker, so the worker's left is the
robot's right). :class:`~.world.World` places the
frame ``distance`` in front of the worker, turned to face it.

The text is a pure function of the spec (fixed number formatting), so the committed default
(``urdf/robot_default.urdf``) is checked against it and a cached copy is reused by name.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

from ..io.atomic import atomic_write

PANDA_PACKAGE = "package://franka_panda/"
ARM_SIDE = {"left": -1.0, "right": 1.0}  # arm -> side of the robot frame's y axis
STAND_DEPTH = 0.30  # along the robot's x [m]
STAND_OVERHANG = 0.12  # beyond each arm base, sideways [m]
STAND_BEHIND = 0.05  # the stand's centre behind the arm bases [m]
CROSSBAR_THICKNESS = 0.04  # the plate the arm bases sit on [m]
LIFT_EFFORT_N, LIFT_VELOCITY = 2000.0, 0.3  # a column lift's push and speed [N, m/s]
DRIVE_EFFORT_N, DRIVE_VELOCITY = 500.0, 0.5  # the mobile base's push and speed [N, m/s]
MAST_DEPTH, MAST_WIDTH = 0.16, 0.30  # the lift's mast, drawn under the crossbar [m]
PLATFORM_HEIGHT = 0.10  # the mobile base's deck; the stand stands on it [m]
GREY = "0.55 0.57 0.6 1"


def _num(x: float) -> str:
    return f"{float(x) + 0.0:.9g}"


def _vec(values) -> str:
    return " ".join(_num(v) for v in values)


def panda_path() -> Path:
    """pybullet_data's Panda description."""
    import pybullet_data

    return Path(pybullet_data.getDataPath()) / "franka_panda" / "panda.urdf"


def _box_link(name: str, size, xyz, mass: float) -> list[str]:
    """A link with one box shape (visual and collision) and a solid box's inertia."""
    sx, sy, sz = size
    inertia = [mass * (b * b + c * c) / 12.0 for b, c in ((sy, sz), (sx, sz), (sx, sy))]
    origin = f'<origin xyz="{_vec(xyz)}" rpy="0 0 0"/>'
    return [
        f'  <link name="{name}">',
        f'    <inertial>{origin}<mass value="{_num(mass)}"/>'
        f'<inertia ixx="{_num(inertia[0])}" ixy="0" ixz="0" iyy="{_num(inertia[1])}" iyz="0"'
        f' izz="{_num(inertia[2])}"/></inertial>',
        f'    <visual>{origin}<geometry><box size="{_vec(size)}"/></geometry>'
        f'<material name="stand_grey"><color rgba="{GREY}"/></material></visual>',
        f'    <collision>{origin}<geometry><box size="{_vec(size)}"/></geometry></collision>',
        "  </link>",
    ]


def _arm_elements(prefix: str) -> list[str]:
    """Every link and joint of the Panda description, names prefixed, meshes by package."""
    root = ET.parse(panda_path()).getroot()
    out = []
    for element in root:
        if element.tag not in ("link", "joint"):
            continue
        element = ET.fromstring(ET.tostring(element))  # a copy: the parse is shared
        element.set("name", prefix + element.get("name"))
        for tag in ("parent", "child"):
            for ref in element.iter(tag):
                ref.set("link", prefix + ref.get("link"))
        for mesh in element.iter("mesh"):
            mesh.set("filename", mesh.get("filename").replace("package://", PANDA_PACKAGE))
        for material in element.iter("material"):
            material.set("name", prefix + material.get("name"))
        ET.indent(element, space="  ", level=1)
        out.append("  " + ET.tostring(element, encoding="unicode").strip())
    return out


def robot_urdf(spec) -> str:
    """The URDF text of the robot described by ``spec`` (a :class:`~.robot.RobotSpec`)."""
    half_span = spec.arm_spacing / 2.0
    width = spec.arm_spacing + 2 * STAND_OVERHANG
    lines = ['<?xml version="1.0"?>',
             "<!-- The dual-arm robot of ergohandover, written by ergohandover.scene.robot_urdf"
             " from RobotSpec. The Franka Panda arms' links and joints are pybullet_data's"
             " franka_panda/panda.urdf (Apache-2.0, LICENSE-franka-panda.txt), changed only by"
             " name prefixes and mesh paths. -->",
             '<robot name="dual_panda">',
             # The root carries a token mass: PyBullet warns about a link without inertia.
             '  <link name="base"><inertial><origin xyz="0 0 0" rpy="0 0 0"/>'
             '<mass value="0.001"/><inertia ixx="1e-06" ixy="0" ixz="0" iyy="1e-06" iyz="0"'
             ' izz="1e-06"/></inertial></link>']
    # The mobile base drives along x; the stand sits on its deck.
    lines += _box_link("mobile_base", (STAND_DEPTH, width, PLATFORM_HEIGHT),
                       (-STAND_BEHIND, 0.0, PLATFORM_HEIGHT / 2), 120.0)
    lines += ['  <joint name="base_drive" type="prismatic"><parent link="base"/>'
              '<child link="mobile_base"/><origin xyz="0 0 0" rpy="0 0 0"/><axis xyz="1 0 0"/>'
              f'<limit lower="0" upper="{_num(spec.drive_range)}"'
              f' effort="{_num(DRIVE_EFFORT_N)}" velocity="{_num(DRIVE_VELOCITY)}"/></joint>']
    stand = spec.mount_height - CROSSBAR_THICKNESS - PLATFORM_HEIGHT
    lines += _box_link("stand", (STAND_DEPTH, width, stand),
                       (-STAND_BEHIND, 0.0, PLATFORM_HEIGHT + stand / 2), 80.0)
    lines += ['  <joint name="stand_mount" type="fixed"><parent link="mobile_base"/>'
              '<child link="stand"/><origin xyz="0 0 0" rpy="0 0 0"/></joint>']
    # The crossbar rides on the lift; at lift 0 its top (the arm bases) is at mount_height.
    crossbar = _box_link("crossbar", (STAND_DEPTH, width, CROSSBAR_THICKNESS),
                         (-STAND_BEHIND, 0.0, -CROSSBAR_THICKNESS / 2), 10.0)
    # The lift's mast under the crossbar, as long as its travel: drawn only (it slides inside
    # the stand, so it has no collision shape), so that a raised crossbar is seen to be held.
    mast = (MAST_DEPTH, MAST_WIDTH, spec.lift_range)
    centre = (-STAND_BEHIND, 0.0, -CROSSBAR_THICKNESS - spec.lift_range / 2)
    crossbar.insert(-1, f'    <visual><origin xyz="{_vec(centre)}" rpy="0 0 0"/>'
                        f'<geometry><box size="{_vec(mast)}"/></geometry>'
                        f'<material name="stand_grey"><color rgba="{GREY}"/></material></visual>')
    lines += crossbar
    lines += ['  <joint name="torso_lift" type="prismatic"><parent link="stand"/>'
              '<child link="crossbar"/>'
              f'<origin xyz="0 0 {_num(spec.mount_height)}" rpy="0 0 0"/><axis xyz="0 0 1"/>'
              f'<limit lower="0" upper="{_num(spec.lift_range)}" effort="{_num(LIFT_EFFORT_N)}"'
              f' velocity="{_num(LIFT_VELOCITY)}"/></joint>']
    for arm, side in ARM_SIDE.items():
        prefix = f"{arm}_"
        lines += [f'  <joint name="{arm}_mount" type="fixed"><parent link="crossbar"/>'
                  f'<child link="{prefix}panda_link0"/>'
                  f'<origin xyz="0 {_num(side * half_span)} 0" rpy="0 0 0"/></joint>']
        lines += _arm_elements(prefix)
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


def resolve_packages(text: str) -> str:
    """The URDF text with ``package://franka_panda/`` replaced by the installed path."""
    return text.replace(PANDA_PACKAGE, str(panda_path().parent) + "/")


def cached_robot_urdf(spec, cache_dir: str | os.PathLike | None = None) -> Path:
    """A loadable URDF file (meshes resolved) for ``spec``, written only if not already there."""
    text = resolve_packages(robot_urdf(spec))
    folder = Path(cache_dir) if cache_dir is not None else (
        Path(tempfile.gettempdir()) / "ergohandover_urdf")
    path = folder / f"robot_{hashlib.sha256(text.encode()).hexdigest()[:16]}.urdf"
    if not path.exists():
        folder.mkdir(parents=True, exist_ok=True)
        atomic_write(path, lambda handle: handle.write(text))
    return path
