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
