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


class StartLattice:
    """Converged postures on a lattice of box locations.

    Args:
        axes: the lattice coordinates along x, y, z (worker frame) [m].
        q: (nx, ny, nz, nq) converged postures at the lattice nodes [rad].
        strategy: (nx, ny, nz) the whole-body strategy each node's posture was solved from.
    """

    def __init__(self, axes: tuple[np.ndarray, np.ndarray, np.ndarray], q: np.ndarray,
                 strategy: np.ndarray):
        self.axes, self.q, self.strategy = axes, q, strategy

    @staticmethod
    def nodes(stature: float) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
        """The lattice axes and its (K, 3) node locations for a worker of ``stature`` [m]."""
        axes = tuple(np.linspace(lo * stature, hi * stature, COUNTS[a])
                     for a, (lo, hi) in EXTENT.items())
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        return axes, grid

    def start(self, locations: np.ndarray) -> np.ndarray:
        """(N, nq) starting postures for (N, 3) box locations (worker frame) [m]."""
        cells, fractions = [], []
        for k, axis in enumerate(self.axes):
            position = (locations[:, k] - axis[0]) / (axis[1] - axis[0])
            cell = np.clip(np.floor(position).astype(np.intp), 0, len(axis) - 2)
            cells.append(cell)
            fractions.append(np.clip(position - cell, 0.0, 1.0))
        q = np.zeros((locations.shape[0], self.q.shape[-1]))
        for corner in range(8):
            dx, dy, dz = (corner >> 2) & 1, (corner >> 1) & 1, corner & 1
            weight = np.ones(locations.shape[0])
            for d, f in zip((dx, dy, dz), fractions, strict=True):
                weight *= f if d else 1.0 - f
            q += weight[:, None] * self.q[cells[0] + dx, cells[1] + dy, cells[2] + dz]
        return q


class FineLattice:
    """Converged-as-today postures at the nodes of a fixed lattice every ``spacing`` (nodes at
    whole multiples of it, worker frame), solved on first use: a location starts from the
    trilinear interpolation of its cell's eight nodes. Each node's posture is a function of the
    node alone (``solve_nodes``), so a location's start never depends on what else was asked
    for, in this process or another.

    Args:
        spacing: the node spacing [m].
        solve_nodes: (K, 3) node locations -> (K, nq) postures [rad].
    """

    OFFSETS = np.array([[(c >> 2) & 1, (c >> 1) & 1, c & 1] for c in range(8)])
    SPAN = 1 << 20  # node indices per axis in a key (+-2^19 nodes: +-5 km at 1 cm)

    def __init__(self, spacing: float, solve_nodes):
        self.spacing, self._solve = spacing, solve_nodes
        self._row: dict[int, int] = {}  # node key -> its row of _q
        self._q: np.ndarray | None = None  # (capacity, nq); rows beyond len(_row) unused

    def _key(self, index: np.ndarray) -> np.ndarray:
        shifted = index + self.SPAN // 2
        return (shifted[..., 0] * self.SPAN + shifted[..., 1]) * self.SPAN + shifted[..., 2]

    def _postures(self, index: np.ndarray) -> np.ndarray:
        """(M, nq) the postures of nodes ``index`` (M, 3), solving those not yet known (a
        batch's corners share few nodes: one lookup per distinct node)."""
        keys, first, inverse = np.unique(self._key(index), return_index=True,
                                         return_inverse=True)
        rows = np.array([self._row.get(k, -1) for k in keys.tolist()], dtype=np.int64)
        missing = np.flatnonzero(rows < 0)
        if missing.size:
            solved = self._solve(index[first[missing]] * self.spacing)
            used = len(self._row)
            if self._q is None or used + len(missing) > len(self._q):
                grown = np.empty((max(2 * (used + len(missing)), 1024), solved.shape[1]))
                if self._q is not None:
                    grown[:used] = self._q[:used]
                self._q = grown
            self._q[used:used + len(missing)] = solved
            rows[missing] = np.arange(used, used + len(missing))
            self._row.update(zip(keys[missing].tolist(), rows[missing].tolist(), strict=True))
        return self._q[rows[inverse.ravel()]]

    def start(self, locations: np.ndarray) -> np.ndarray:
        """(N, nq) starting postures for (N, 3) box locations (worker frame) [m]."""
        position = locations / self.spacing
        base = np.floor(position).astype(np.int64)
        fraction = position - base
        corners = base[:, None, :] + self.OFFSETS[None]  # (N, 8, 3)
        q = self._postures(corners.reshape(-1, 3)).reshape(len(locations), 8, -1)
        weight = np.prod(np.where(self.OFFSETS[None] == 1, fraction[:, None, :],
                                  1.0 - fraction[:, None, :]), axis=2)  # (N, 8)
        return np.einsum("nc,ncq->nq", weight, q)
