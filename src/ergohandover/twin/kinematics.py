"""Batched forward kinematics, Jacobians and centre of mass of the worker, in numpy.

Built from the same ``Skeleton`` as the URDF and never from PyBullet, so N postures are
evaluated in one vectorised pass: the only Python loop runs over the ~30 joints. Jacobians are
analytic (axis × lever arm for revolute joints) and taken from the forward-kinematics result.

Angles are in [rad]; q has one column per movable joint in ``KinematicModel.joint_names``
order, which is the skeleton's tree order: ankle, knee, hip, lumbar (flexion, side bend,
twist), neck (same three), then the left arm and the right arm, each clavicle_elevation,
shoulder_flexion, shoulder_abduction, shoulder_rotation, elbow_flexion, forearm_pronation,
wrist_flexion, wrist_deviation.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from .skeleton import Skeleton

ExtraMasses = Mapping[str, "float | np.ndarray"]
"""Point masses at link origins: link name -> mass [kg], a float or (N,)."""


class JointStep(NamedTuple):
    """One joint, precompiled: ``origin`` as (component, value) pairs, axis = sign × e_axis."""

    parent: int
    child: int
    origin: tuple[tuple[int, float], ...]
    col: int  # column in q, -1 for a fixed joint
    axis: int
    sign: float


def _sparse(vec) -> tuple[tuple[int, float], ...]:
    """Non-zero components of a 3-vector as (index, value) pairs."""
    return tuple((i, float(v)) for i, v in enumerate(vec) if v != 0.0)


def _add_times(out: np.ndarray, rot: np.ndarray, vec, scratch: np.ndarray) -> None:
    """``out += rot @ vec`` for (3, N) ``out``, (3, 3, N) ``rot`` and sparse ``vec``.

    In-place products into a scratch buffer: allocating a temporary per joint cost more than
    the arithmetic.
    """
    for i, value in vec:
        np.multiply(rot[:, i], value, out=scratch)
        out += scratch


def _lookup(table: dict[str, int], name: str, what: str) -> int:
    """``table[name]``, or a KeyError that lists the valid names."""
    if name not in table:
        raise KeyError(f"no {what} {name!r}; valid: {', '.join(table)}")
    return table[name]


class KinematicModel:
    """Kinematics of one worker's skeleton, batched over postures.

    Attributes:
        skeleton: The tree it was built from.
        joint_names: Movable joints in q-column order (see the module docstring).
        link_names: All links, base ``feet`` first (the L axis of ``KinematicState``).
        lower, upper: (nq,) joint limits [rad].
        link_mass: (L,) link masses [kg]; ``total_mass`` is their sum [kg].
        ancestors: (L, nq) bool, True where joint j moves link l.
        steps: the joints in tree order as :class:`JointStep` (what the compiled solver packs).
        joint_children: (nq,) the link each movable joint turns.
        mass_points: (link index, COM offset as (component, value) pairs) of each link with
            mass.
    """

    def __init__(self, skeleton: Skeleton) -> None:
        self.skeleton = skeleton
        self.link_names = tuple(link.name for link in skeleton.links)
        self._link = {name: i for i, name in enumerate(self.link_names)}
        movable = skeleton.movable_joints
        self.joint_names = tuple(j.name for j in movable)
        self._joint = {name: i for i, name in enumerate(self.joint_names)}
        self.lower = np.array([j.lower for j in movable])  # (nq,)
        self.upper = np.array([j.upper for j in movable])  # (nq,)
        self.link_mass = np.array([link.mass for link in skeleton.links])  # (L,)
        self.total_mass = float(self.link_mass.sum())
        self.mass_points = [(i, _sparse(link.com))
                            for i, link in enumerate(skeleton.links) if link.mass]
        self.ancestors = np.zeros((len(self.link_names), len(movable)), dtype=bool)
        self.steps: list[JointStep] = []
        for joint in skeleton.joints:
            parent, child = self._link[joint.parent], self._link[joint.child]
            col = self._joint.get(joint.name, -1)
            self.ancestors[child] = self.ancestors[parent]
            axis = int(np.argmax(np.abs(joint.axis)))
            if col >= 0:
                self.ancestors[child, col] = True
                # Frames are world-aligned at q = 0, so anatomical axes are coordinate axes;
                # turning about one changes only two columns of R, which keeps FK cheap.
                if not np.array_equal(np.abs(joint.axis), np.eye(3)[axis]):
                    raise ValueError(f"{joint.name}: axis {joint.axis} is not ± a coordinate axis")
            sign = float(np.sign(joint.axis[axis]))
            self.steps.append(JointStep(parent, child, _sparse(joint.origin), col, axis, sign))
        self._signs = np.array([st.sign for st in self.steps if st.col >= 0])  # (nq,)
        # The link each movable joint turns, in q-column order.
        self.joint_children = np.array([st.child for st in self.steps if st.col >= 0])

    @property
    def nq(self) -> int:
        """Number of movable joints."""
        return len(self.joint_names)

    def index(self, name: str) -> int:
        """Column of the movable joint ``name`` in q."""
        return _lookup(self._joint, name, "movable joint")

    def link_index(self, name: str) -> int:
        """Position of link ``name`` along the L axis."""
        return _lookup(self._link, name, "link")

    def forward(self, q: np.ndarray) -> KinematicState:
        """Link frames of N postures.

        Args:
            q: (N, nq) joint angles [rad]; a single (nq,) posture is treated as N = 1.

        Returns:
            The state: link frame positions [m] and rotations, world frame.
        """
        q = np.atleast_2d(np.asarray(q, dtype=float))
        if q.ndim != 2 or q.shape[1] != self.nq:
            raise ValueError(f"q must have shape (N, {self.nq}), got {q.shape}")
        n, n_links = q.shape[0], len(self.link_names)
        # Posture-last storage: every product below runs in place over contiguous rows of N.
        sin = np.sin(q.T) * self._signs[:, None]  # (nq, N), axis sign folded into the angle
        cos = np.cos(q.T)  # (nq, N)
        pos = np.empty((n_links, 3, n))  # every entry is written below
        rot = np.empty((n_links, 3, 3, n))
        pos[0], rot[0] = 0.0, np.eye(3)[:, :, None]  # the base sits at the world origin
        axes = np.empty((self.nq, 3, n))  # world joint axes
        scratch = np.empty((3, n))
        for st in self.steps:
            r = rot[st.parent]  # (3, 3, N); r[:, i] is the parent's i axis in the world
            pos[st.child] = pos[st.parent]
            _add_times(pos[st.child], r, st.origin, scratch)
            if st.col < 0:
                rot[st.child] = r
                continue
            # About ± e_i: axis i stays, the next two axes j, k turn in their plane.
            i, j, k = st.axis, (st.axis + 1) % 3, (st.axis + 2) % 3
            out, c, s = rot[st.child], cos[st.col], sin[st.col]
            out[:, i] = r[:, i]
            np.multiply(r[:, j], c, out=out[:, j])
            out[:, j] += np.multiply(r[:, k], s, out=scratch)
            np.multiply(r[:, k], c, out=out[:, k])
            out[:, k] -= np.multiply(r[:, j], s, out=scratch)
            np.multiply(r[:, i], st.sign, out=axes[st.col])
        return KinematicState(self, q, pos, rot, axes)

    def point_jacobian(self, q: np.ndarray, link: str, offset=None) -> np.ndarray:
        """(N, 3, nq) Jacobian of a point fixed in ``link`` [m/rad]; see KinematicState."""
        return self.forward(q).point_jacobian(link, offset)

    def angular_jacobian(self, q: np.ndarray, link: str) -> np.ndarray:
        """(N, 3, nq) angular-velocity Jacobian of ``link`` [1]; see KinematicState."""
        return self.forward(q).angular_jacobian(link)

    def com(self, q: np.ndarray, extra: ExtraMasses | None = None) -> np.ndarray:
        """(N, 3) whole-body centre of mass [m]; see KinematicState.com."""
        return self.forward(q).com(extra)

    def com_jacobian(self, q: np.ndarray, extra: ExtraMasses | None = None) -> np.ndarray:
        """(N, 3, nq) Jacobian of the centre of mass [m/rad]; see KinematicState.com_jacobian."""
        return self.forward(q).com_jacobian(extra)


class KinematicState:
    """Forward kinematics of N postures; reuse one to take several Jacobians from one FK pass.

    Arrays are stored posture-last for speed; the accessors return (N, ...) views of them.
    """

    def __init__(self, model: KinematicModel, q: np.ndarray, pos: np.ndarray, rot: np.ndarray,
                 axes: np.ndarray) -> None:
        self.model, self.q = model, q  # q: (N, nq) [rad]
        self._pos, self._rot, self._axes = pos, rot, axes  # (L, 3, N), (L, 3, 3, N), (nq, 3, N)
        # A joint sits on its child's origin.
        self._joint_pos = pos[model.joint_children]  # (nq, 3, N)

    @property
    def positions(self) -> np.ndarray:
        """(N, L, 3) link frame origins [m], L in ``model.link_names`` order (a view)."""
        return self._pos.transpose(2, 0, 1)

    @property
    def rotations(self) -> np.ndarray:
        """(N, L, 3, 3) link rotations, world = R @ local (a view)."""
        return self._rot.transpose(3, 0, 1, 2)

    def position(self, link: str) -> np.ndarray:
        """(N, 3) world position of the origin of ``link`` [m] (a view)."""
        return self._pos[self.model.link_index(link)].T

    def rotation(self, link: str) -> np.ndarray:
        """(N, 3, 3) rotation of ``link``; its columns are the link's axes in the world."""
        return self._rot[self.model.link_index(link)].transpose(2, 0, 1)

    def _point(self, i: int, offset) -> np.ndarray:
        """(3, N) world position [m] of ``offset`` ((3,) or (N, 3) [m]) in link ``i``."""
        if offset is None:
            return self._pos[i]
        offset = np.asarray(offset, dtype=float)
        spec = "abn,b->an" if offset.ndim == 1 else "abn,nb->an"
        return self._pos[i] + np.einsum(spec, self._rot[i], offset)

    def point(self, link: str, offset=None) -> np.ndarray:
        """(N, 3) world position [m] of a point at ``offset`` ((3,) or (N, 3), link frame [m])."""
        return self._point(self.model.link_index(link), offset).T

    def point_jacobian(self, link: str, offset=None) -> np.ndarray:
        """Jacobian of a point fixed in ``link``: d(point)/dq [m/rad].

        Args:
            link: Link name.
            offset: (3,) or (N, 3) point in the link frame [m]; default the link origin.

        Returns:
            (N, 3, nq) (a view); column j is axis_j × (point − joint_j) for the joints above
            the link, zero for the others.
        """
        i = self.model.link_index(link)
        cols = np.flatnonzero(self.model.ancestors[i])
        lever = self._point(i, offset)[None] - self._joint_pos[cols]  # (k, 3, N)
        return self._cross_jacobian(self._axes[cols], lever, cols)

    def angular_jacobian(self, link: str) -> np.ndarray:
        """(N, 3, nq) angular-velocity Jacobian of ``link`` (a view): joint j's world axis."""
        cols = np.flatnonzero(self.model.ancestors[self.model.link_index(link)])
        jac = np.zeros((self.model.nq, 3, self.q.shape[0]))
        jac[cols] = self._axes[cols]
        return jac.transpose(2, 1, 0)

    def _masses(self, extra: ExtraMasses | None):
        """Point masses (P, N) [kg], their positions (P, 3, N) [m] and links (P,).

        One entry per link with mass (at its COM), then one per extra mass (at its link origin).
        """
        n, extra = self.q.shape[0], extra or {}
        links = [i for i, _ in self.model.mass_points] + [self.model.link_index(e) for e in extra]
        mass = [np.full(n, self.model.link_mass[i]) for i, _ in self.model.mass_points]
        mass += [np.broadcast_to(np.asarray(m, dtype=float), (n,)) for m in extra.values()]
        where = self._pos[links]  # (P, 3, N) copy; link COMs get their offsets added
        scratch = np.empty((3, n))
        for p, (i, com) in enumerate(self.model.mass_points):
            _add_times(where[p], self._rot[i], com, scratch)
        return np.array(mass), where, links

    def com(self, extra: ExtraMasses | None = None) -> np.ndarray:
        """Whole-body centre of mass.

        Args:
            extra: Optional point masses at link origins, link name -> mass [kg] (float or
                (N,)), e.g. ``{"left_grip": box / 2, "right_grip": box / 2}``.

        Returns:
            (N, 3) centre of mass [m], world frame.
        """
        mass, where, _ = self._masses(extra)
        return (np.einsum("pn,pcn->cn", mass, where) / mass.sum(axis=0)).T

    @property
    def joint_axes(self) -> np.ndarray:
        """(nq, 3, N) the joints' world axes (a view)."""
        return self._axes

    def subtree_levers(self, extra: ExtraMasses | None = None) -> np.ndarray:
        """(nq, 3, N) Σ m (c − p_j) over the masses that joint j moves [kg m]: the
        mass-weighted lever arm of its subtree about the joint (``extra`` as in :meth:`com`)."""
        mass, where, links = self._masses(extra)
        moved = self.model.ancestors[links].T.astype(float)  # (nq, P)
        sub_mass = moved @ mass  # (nq, N)
        sub_moment = np.tensordot(moved, mass[:, None] * where, axes=(1, 0))  # (nq, 3, N)
        return sub_moment - sub_mass[:, None] * self._joint_pos

    def com_jacobian(self, extra: ExtraMasses | None = None) -> np.ndarray:
        """(N, 3, nq) Jacobian of ``com(extra)`` [m/rad] (a view).

        Column j is axis_j × Σ m (c − p_j) / M over the masses that joint j moves: the
        mass-weighted lever arm of its subtree.
        """
        mass = self._masses(extra)[0]
        lever = self.subtree_levers(extra)
        lever /= mass.sum(axis=0)
        return self._cross_jacobian(self._axes, lever, np.arange(self.model.nq))

    def _cross_jacobian(self, axes: np.ndarray, lever: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """(N, 3, nq) view of a Jacobian whose q-columns ``cols`` are axes × lever, (k, 3, N).

        Written row by row: np.cross would move the component axis last and back (two copies).
        """
        jac = np.zeros((self.model.nq, 3, self.q.shape[0]))
        for c in range(3):
            i, j = (c + 1) % 3, (c + 2) % 3
            jac[cols, c] = axes[:, i] * lever[:, j] - axes[:, j] * lever[:, i]
        return jac.transpose(2, 1, 0)
