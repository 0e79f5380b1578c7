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
from numba import njit

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
        self._packed = None  # link index, point and radius of every probe, built on first use

    @staticmethod
    @functools.lru_cache(maxsize=16)
    def of(skeleton: Skeleton) -> BodyProbes:
        """The probes of ``skeleton``, built once."""
        return BodyProbes(skeleton)

    def box_hits_body(self, st: KinematicState, centre: np.ndarray,
                      half: np.ndarray) -> np.ndarray:
        """(N,) True where a box at ``centre`` (N, 3) with half extents ``half`` (3,) [m],
        world frame, contains any probe (compiled: a location stops at its first hit)."""
        if self._packed is None:
            model = st.model
            self._packed = (
                np.concatenate([np.full(len(p), model.link_index(link), np.int64)
                                for link, p in zip(self.links, self.points, strict=True)]),
                np.concatenate(self.points),
                np.concatenate([np.full(len(p), r) for p, r in zip(self.points, self.radii,
                                                                   strict=True)]))
        hit = np.empty(centre.shape[0], dtype=np.bool_)
        _box_hits(st.positions, st.rotations, *self._packed,
                  np.ascontiguousarray(centre, dtype=float),
                  np.asarray(half, dtype=float), hit)
        return hit

    def box_hits_body_numpy(self, st: KinematicState, centre: np.ndarray,
                            half: np.ndarray) -> np.ndarray:
        """:meth:`box_hits_body` in numpy, batched over postures: the reference."""
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


@njit(cache=True, nogil=True)
def _box_hits(positions, rotations, probe_link, probe_point, probe_radius, centre, half, out):
    """``out[i]``: does the box at ``centre[i]`` contain a probe of posture i? positions
    (N, L, 3), rotations (N, L, 3, 3), probes (P,) links, (P, 3) points, (P,) radii.

    The arithmetic of the numpy version, in its order (the rotated point's three products
    summed first, then the link origin added), so both give the same answer.
    """
    for i in range(centre.shape[0]):
        hit = False
        for p in range(probe_link.shape[0]):
            link, inside = probe_link[p], True
            px, py, pz = probe_point[p, 0], probe_point[p, 1], probe_point[p, 2]
            for c in range(3):
                rot = rotations[i, link, c]
                world = positions[i, link, c] + (rot[0] * px + rot[1] * py + rot[2] * pz)
                if not abs(world - centre[i, c]) < half[c] + probe_radius[p]:
                    inside = False
                    break
            if inside:
                hit = True
                break
        out[i] = hit
