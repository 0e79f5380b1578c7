"""Where the posture solver starts: converged postures on a coarse lattice, interpolated.

Solving every location from one standing posture needs ~40 iterations, most of them spent
walking the trunk and arms toward the region of the answer. Instead, postures are solved once,
to convergence, on a coarse lattice of box locations scaled to the worker's stature, and each
location starts from the trilinear interpolation of its lattice cell — a fixed, continuous
function of the location alone, so results stay deterministic and independent of the batch.
"""

from __future__ import annotations

import numpy as np

# Lattice extent as fractions of stature (worker frame: x right, y up, z forward) and counts.
# It covers every boundary in use with a margin; locations outside it start from its edge.
EXTENT = {"x": (-0.28, 0.28), "y": (0.04, 1.25), "z": (0.05, 0.52)}
COUNTS = {"x": 9, "y": 16, "z": 9}
OFFSETS = np.array([[(c >> 2) & 1, (c >> 1) & 1, c & 1] for c in range(8)])
"""A cell's eight corners as steps along x, y, z from its lowest corner."""


def corner_weights(fraction: np.ndarray) -> np.ndarray:
    """(N, 8) trilinear weights of a cell's corners (:data:`OFFSETS`) at (N, 3) fractions of the
    cell along x, y, z."""
    return np.prod(np.where(OFFSETS[None] == 1, fraction[:, None, :], 1.0 - fraction[:, None, :]),
                   axis=2)


class StartLattice:
    """Converged postures on a lattice of box locations, each node solved the first time a
    location's cell needs it.

    A node's posture is a function of the node alone (``solve_nodes`` solves each location on
    its own), so solving only the nodes a grid's cells touch gives the same starts as solving
    the whole lattice first, whatever was asked before or in another process.

    Args:
        axes: the lattice coordinates along x, y, z (worker frame) [m].
        solve_nodes: (K, 3) node locations -> (K, nq) converged postures [rad] and (K,) the
            whole-body strategy each was solved from.
        nq: the number of joints.
    """

    def __init__(self, axes: tuple[np.ndarray, np.ndarray, np.ndarray], solve_nodes,
                 nq: int):
        self.axes, self._solve = axes, solve_nodes
        shape = tuple(len(a) for a in axes)
        self._nodes = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        self._q = np.zeros((*shape, nq))
        self._strategy = np.full(shape, "", dtype=object)
        self._solved = np.zeros(shape, dtype=bool)

    @staticmethod
    def nodes(stature: float) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
        """The lattice axes and its (K, 3) node locations for a worker of ``stature`` [m]."""
        axes = tuple(np.linspace(lo * stature, hi * stature, COUNTS[a])
                     for a, (lo, hi) in EXTENT.items())
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        return axes, grid

    @property
    def q(self) -> np.ndarray:
        """(nx, ny, nz, nq) the postures at every node [rad] (solving those not yet solved)."""
        self._solve_flat(np.arange(self._solved.size))
        return self._q

    @property
    def strategy(self) -> np.ndarray:
        """(nx, ny, nz) the strategy every node's posture was solved from."""
        self._solve_flat(np.arange(self._solved.size))
        return self._strategy

    def prepare(self, locations: np.ndarray) -> None:
        """Solve the nodes of every cell of (N, 3) box locations (worker frame) [m], e.g.
        before worker processes fork, so that they share them."""
        cells, _ = self._cells(np.asarray(locations, dtype=float).reshape(-1, 3))
        corners = np.stack(cells, axis=1)[:, None, :] + OFFSETS[None]  # (N, 8, 3)
        self._solve_flat(np.ravel_multi_index(corners.reshape(-1, 3).T, self._solved.shape))

    def start(self, locations: np.ndarray) -> np.ndarray:
        """(N, nq) starting postures for (N, 3) box locations (worker frame) [m]."""
        self.prepare(locations)
        cells, fractions = self._cells(locations)
        weight = corner_weights(np.stack(fractions, axis=1))
        q = np.zeros((locations.shape[0], self._q.shape[-1]))
        for corner, (dx, dy, dz) in enumerate(OFFSETS):
            q += weight[:, corner, None] * self._q[cells[0] + dx, cells[1] + dy, cells[2] + dz]
        return q

    def _cells(self, locations: np.ndarray) -> tuple[list[np.ndarray], list[np.ndarray]]:
        """Each location's cell (its lowest corner's index along x, y, z) and its fractions
        along them; a location outside the lattice takes the edge cell's nearest face."""
        cells, fractions = [], []
        for k, axis in enumerate(self.axes):
            position = (locations[:, k] - axis[0]) / (axis[1] - axis[0])
            cell = np.clip(np.floor(position).astype(np.intp), 0, len(axis) - 2)
            cells.append(cell)
            fractions.append(np.clip(position - cell, 0.0, 1.0))
        return cells, fractions

    def _solve_flat(self, flat: np.ndarray) -> None:
        """Solve the nodes of flat indices ``flat`` not yet solved, in one batch."""
        todo = np.unique(flat)
        todo = todo[~self._solved.reshape(-1)[todo]]
        if todo.size == 0:
            return
        q, strategy = self._solve(self._nodes[todo])
        index = np.unravel_index(todo, self._solved.shape)
        self._q[index], self._strategy[index], self._solved[index] = q, strategy, True


class FineLattice:
    """Today's solves at the nodes of a fixed lattice every ``spacing`` (nodes at whole
    multiples of it, worker frame), solved on first use, each kept with the code of its scores:
    a location starts from the trilinear interpolation of its cell's eight nodes, and
    :meth:`unsure` tells which locations that interpolation may score differently from today's
    solve. Each node's posture and code are functions of the node alone (``solve_nodes``), so
    a location's start never depends on what else was asked for, in this process or another.

    Args:
        spacing: the node spacing [m].
        solve_nodes: (K, 3) node locations -> (K, nq) postures [rad] and (K,) int64 codes.
    """

    SPAN = 1 << 20  # node indices per axis in a key (+-2^19 nodes: +-5 km at 1 cm)
    # The cell's four edges along each axis (bit 2: x, 1: y, 0: z of the corner number): their
    # first and last corners, (3, 4) each.
    EDGE_FROM = np.array([[c for c in range(8) if not c & bit] for bit in (4, 2, 1)])
    EDGE_TO = EDGE_FROM | np.array([4, 2, 1])[:, None]

    def __init__(self, spacing: float, solve_nodes):
        self.spacing, self._solve = spacing, solve_nodes
        self._keys = np.empty(0, np.int64)  # the known nodes' keys, sorted
        self._rows = np.empty(0, np.int64)  # their rows of _q and _code, in _keys' order
        self._q: np.ndarray | None = None  # (capacity, nq); rows beyond len(_keys) unused
        self._code = np.empty(0, np.int64)  # (capacity,)

    def _key(self, index: np.ndarray) -> np.ndarray:
        shifted = index + self.SPAN // 2
        return (shifted[..., 0] * self.SPAN + shifted[..., 1]) * self.SPAN + shifted[..., 2]

    def _nodes(self, index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(M, nq) postures and (M,) codes of nodes ``index`` (M, 3), solving those not yet
        known (a batch's corners share few nodes: each distinct node is solved once)."""
        keys, first, inverse = np.unique(self._key(index), return_index=True,
                                         return_inverse=True)
        at = np.minimum(np.searchsorted(self._keys, keys), max(len(self._keys) - 1, 0))
        known = (self._keys[at] == keys) if len(self._keys) else np.zeros(len(keys), bool)
        missing = np.flatnonzero(~known)
        if missing.size:
            q, code = self._solve(index[first[missing]] * self.spacing)
            used = len(self._keys)
            if self._q is None or used + len(missing) > len(self._q):
                size = max(2 * (used + len(missing)), 1024)
                grown, codes = np.empty((size, q.shape[1])), np.empty(size, np.int64)
                if self._q is not None:
                    grown[:used], codes[:used] = self._q[:used], self._code[:used]
                self._q, self._code = grown, codes
            self._q[used:used + len(missing)], self._code[used:used + len(missing)] = q, code
            where = np.searchsorted(self._keys, keys[missing])
            self._keys = np.insert(self._keys, where, keys[missing])
            self._rows = np.insert(self._rows, where, np.arange(used, used + len(missing)))
        rows = self._rows[np.searchsorted(self._keys, keys)][inverse.ravel()]
        return self._q[rows], self._code[rows]

    def corners(self, locations: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The cells of (N, 3) box locations (worker frame) [m]: their corners' postures
        (N, 8, nq) [rad] and codes (N, 8), and each corner's trilinear weight (N, 8)."""
        position = locations / self.spacing
        base = np.floor(position).astype(np.int64)
        fraction = position - base
        corners = base[:, None, :] + OFFSETS[None]  # (N, 8, 3)
        q, code = self._nodes(corners.reshape(-1, 3))
        return (q.reshape(len(locations), 8, -1), code.reshape(len(locations), 8),
                corner_weights(fraction))

    @staticmethod
    def interpolate(q: np.ndarray, weight: np.ndarray) -> np.ndarray:
        """(N, nq) postures from corner postures (N, 8, nq) and weights (N, 8) of
        :meth:`corners`."""
        return np.einsum("nc,ncq->nq", weight, q)

    @classmethod
    def unsure(cls, q: np.ndarray, code: np.ndarray, found: np.ndarray,
               max_twist: float) -> np.ndarray:
        """(N,) bool: the locations whose interpolated result may differ from today's solve.

        A location is sure when its code ``found`` (N,) is that of all eight corners (``code``,
        (N, 8)), or is one of theirs and the cell is smooth: along each axis its four parallel
        edges change every joint alike, within ``max_twist`` [rad] (``q``, (N, 8, nq)). Why:
        today's solve is not converged, so its posture jumps where its path changes; a cell
        holding such a jump has edges that disagree, and a cell whose corners score alike
        rarely holds a location scoring otherwise.
        """
        alike = code == found[:, None]
        unsure = ~alike.all(axis=1)
        tested = np.flatnonzero(unsure & alike.any(axis=1))  # only these need the twist
        change = q[tested[:, None, None], cls.EDGE_TO] - q[tested[:, None, None],
                                                           cls.EDGE_FROM]  # (M, 3, 4, nq)
        twist = np.abs(change - change.mean(axis=2, keepdims=True)).max(axis=(1, 2, 3))
        unsure[tested[twist <= max_twist]] = False
        return unsure
