"""Does the box intersect the worker's body? Box-versus-probe tests, batched over postures.

The body (not the arms and hands, which hold the box) is represented by probe points sampled
from its collision shapes, each with a radius: a grid through every box shape, points along
every capsule axis, sphere centres. The box is axis-aligned in the worker frame, hence in the
world frame. A probe inside the box grown by the probe's radius is a collision (conservative
at the box's corners, where the grown box is square rather than rounded).
"""

from __future__ import annotations

import functools

import numpy as np

from .kinematics import KinematicState
from .skeleton import Skeleton

HOLDING_LINKS = ("clavicle", "upper_arm", "forearm", "hand", "grip")


def _probe_points(shape) -> tuple[np.ndarray, float]:
    """Probe points (P, 3) in the link frame and their radius [m] for one shape."""
    centre = np.array(shape.xyz)
    if shape.kind == "box":
        half = np.array(shape.size) / 2.0
        axes = [np.linspace(-h, h, 3) for h in half]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        return centre + grid, 0.0
    if shape.kind == "capsule":
        radius, length = shape.size
        roll = shape.rpy[0]
        axis = np.array([0.0, -np.sin(roll), np.cos(roll)])  # the capsule's z after its roll
        ts = np.linspace(-length / 2.0, length / 2.0, 5)
        return centre + ts[:, None] * axis, radius
    return centre[None], shape.size[0]  # sphere


class BodyProbes:
    """Probe points of the torso, head and legs of one skeleton."""

    def __init__(self, skeleton: Skeleton):
        self.links, self.points, self.radii = [], [], []
        for link in skeleton.links:
            if any(part in link.name for part in HOLDING_LINKS):
                continue
            for shape in link.shapes:
                points, radius = _probe_points(shape)
                self.links.append(link.name)
                self.points.append(points)
                self.radii.append(radius)

    @staticmethod
    @functools.lru_cache(maxsize=16)
    def of(skeleton: Skeleton) -> BodyProbes:
        """The probes of ``skeleton``, built once."""
        return BodyProbes(skeleton)

    def box_hits_body(self, st: KinematicState, centre: np.ndarray,
                      half: np.ndarray) -> np.ndarray:
        """(N,) True where a box at ``centre`` (N, 3) with half extents ``half`` (3,) [m],
        world frame, contains any probe."""
        hit = np.zeros(centre.shape[0], dtype=bool)
        for link, points, radius in zip(self.links, self.points, self.radii, strict=True):
            world = st.point(link)[:, None, :] + np.einsum(
                "nij,pj->npi", st.rotation(link), points)  # (N, P, 3)
            gap = np.abs(world - centre[:, None, :])  # (N, P, 3)
            limit = half + radius
            # Three comparisons combined with &: np.all over a length-3 axis costs several
            # times more.
            inside = ((gap[..., 0] < limit[0]) & (gap[..., 1] < limit[1])
                      & (gap[..., 2] < limit[2]))
            hit |= inside.any(axis=1)
        return hit
