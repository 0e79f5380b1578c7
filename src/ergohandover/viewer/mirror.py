"""The PyBullet scene of a handover, mirrored into a viser scene.

Every visual shape of every body of a :class:`~..scene.world.World` (the worker's twin, the robot,
the box, a floor) becomes a mesh of the viser scene, made from the same URDFs the study loads
into PyBullet; :meth:`SceneMirror.update` copies each link's pose from PyBullet. Both scenes use
PyBullet's world frame (z up; :mod:`..frames` converts worker-frame locations), so nothing is
converted here.
"""

from __future__ import annotations

from functools import cache
from typing import NamedTuple

import numpy as np
import trimesh

from ..scene.world import World

FLOOR_RGBA = (0.82, 0.82, 0.80, 1.0)
FLOOR_HALF_EXTENTS = (1.8, 1.5, 0.005)
FLOOR_CENTRE = (0.5, 0.0, -0.005)  # under the worker and the robot (as the scene renderer's)


class Shape(NamedTuple):
    """One visual shape: the body and link it moves with, its pose in the link's frame."""

    body: int
    link: int
    position: tuple
    orientation: tuple  # x, y, z, w (PyBullet's order)


@cache
def _mesh_file(path: str, scale: tuple) -> trimesh.Trimesh:
    """A mesh file's triangles, scaled (the robot's meshes repeat across its two arms)."""
    mesh = trimesh.load(path, force="mesh")
    mesh.apply_scale(scale)
    return mesh


def shape_mesh(kind: int, dimensions, path: bytes, p) -> trimesh.Trimesh | None:
    """The triangles of a PyBullet visual shape (``getVisualShapeData``'s geometry type,
    dimensions and mesh file); None for a type it cannot show (a plane, a height field)."""
    if kind == p.GEOM_BOX:
        return trimesh.creation.box(extents=dimensions)
    if kind == p.GEOM_SPHERE:
        return trimesh.creation.icosphere(subdivisions=2, radius=dimensions[0])
    if kind == p.GEOM_CYLINDER:
        return trimesh.creation.cylinder(radius=dimensions[1], height=dimensions[0], sections=24)
    if kind == p.GEOM_CAPSULE:
        return trimesh.creation.capsule(height=dimensions[0], radius=dimensions[1],
                                        count=(16, 16))
    if kind == p.GEOM_MESH:
        return _mesh_file(path.decode(), tuple(map(float, dimensions)))
    return None


def xyzw_to_wxyz(q) -> np.ndarray:
    return np.array([q[3], q[0], q[1], q[2]])


class SceneMirror:
    """A viser scene that shows a :class:`World`: every visual shape of the worker, the robot
    and the box, and a floor, under ``/scene``.

    Args:
        world: the PyBullet scene (its client stays the caller's).
        server: the viser server (or anything with its ``scene`` and ``atomic()``).
    """

    def __init__(self, world: World, server):
        self.world, self.server, p = world, server, world.p
        scene = server.scene
        self.shapes: dict[str, Shape] = {}
        self.handles = {}
        floor = trimesh.creation.box(extents=2 * np.asarray(FLOOR_HALF_EXTENTS))
        scene.add_mesh_simple("/scene/floor", floor.vertices, floor.faces,
                              color=tuple(int(255 * c) for c in FLOOR_RGBA[:3]),
                              position=FLOOR_CENTRE, receive_shadow=True)
        bodies = {"worker": world.worker.body_id, "robot": world.robot.body,
                  "box": world.box.body_id}
        for name, body in bodies.items():
            for k, data in enumerate(p.getVisualShapeData(body, physicsClientId=world.client)):
                _, link, kind, dimensions, path, position, orientation, rgba = data[:8]
                mesh = shape_mesh(kind, dimensions, path, p)
                if mesh is None:
                    continue
                node = f"/scene/{name}/{k}"
                self.shapes[node] = Shape(body, link, position, orientation)
                self.handles[node] = scene.add_mesh_simple(
                    node, mesh.vertices.astype(np.float32), mesh.faces.astype(np.uint32),
                    color=tuple(int(255 * c) for c in rgba[:3]), opacity=float(rgba[3]),
                    side="double" if kind == p.GEOM_MESH else "front")
        self.update()

    def link_pose(self, body: int, link: int) -> tuple:
        """A link's URDF frame in the world (the base's for ``link`` -1), position and x, y,
        z, w: ``getVisualShapeData`` gives each shape's pose in that frame."""
        p, client = self.world.p, self.world.client
        if link >= 0:
            state = p.getLinkState(body, link, computeForwardKinematics=True,
                                   physicsClientId=client)
            return state[4], state[5]
        # The base's pose is its centre of mass: undo its inertial offset.
        at, turn = p.getBasePositionAndOrientation(body, physicsClientId=client)
        inertial = p.getDynamicsInfo(body, -1, physicsClientId=client)[3:5]
        return p.multiplyTransforms(at, turn, *p.invertTransform(*inertial))

    def update(self) -> None:
        """Copy every shape's pose from PyBullet (call after posing the world)."""
        p, frames = self.world.p, {}
        with self.server.atomic():  # the browser sees one new pose, not a link at a time
            for node, shape in self.shapes.items():
                key = (shape.body, shape.link)
                if key not in frames:
                    frames[key] = self.link_pose(*key)
                at, turn = p.multiplyTransforms(*frames[key], shape.position,
                                                shape.orientation)
                handle = self.handles[node]
                handle.position = np.asarray(at)
                handle.wxyz = xyzw_to_wxyz(turn)

