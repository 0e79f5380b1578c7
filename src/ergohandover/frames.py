"""The worker frame and PyBullet's world frame: the only place axes are swapped.

Worker frame (the paper's Unity convention, used by every CSV, flag and figure): origin on the
floor midway between the feet, **x** to the worker's right, **y** up, **z** forward. It is
left-handed, as Unity is.

World frame (PyBullet): right-handed, z up. The worker stands at the origin facing +x, so the
worker's left is +y. Hence ``world = (z_w, -x_w, y_w)``.
"""

from __future__ import annotations

import numpy as np

# Rows map a worker-frame vector to world coordinates: world = WORKER_TO_WORLD @ worker.
WORKER_TO_WORLD = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
WORLD_TO_WORKER = WORKER_TO_WORLD.T


def worker_to_world(points: np.ndarray) -> np.ndarray:
    """Convert points or vectors from the worker frame to PyBullet's world frame.

    Args:
        points: (..., 3) coordinates in the worker frame [m].

    Returns:
        (..., 3) coordinates in the world frame [m].
    """
    return np.asarray(points, dtype=float) @ WORKER_TO_WORLD.T


def world_to_worker(points: np.ndarray) -> np.ndarray:
    """Convert points or vectors from PyBullet's world frame to the worker frame.

    Args:
        points: (..., 3) coordinates in the world frame [m].

    Returns:
        (..., 3) coordinates in the worker frame [m].
    """
    return np.asarray(points, dtype=float) @ WORLD_TO_WORKER.T


def rotation_to_worker(matrix: np.ndarray) -> np.ndarray:
    """A rotation matrix (3, 3) of the world frame as the same rotation of the worker frame
    (the two frames differ by a reflection, so the result is a rotation too)."""
    return WORLD_TO_WORKER @ np.asarray(matrix, dtype=float) @ WORKER_TO_WORLD
