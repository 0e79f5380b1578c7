"""The grid of candidate handover locations: a boundary sampled every ``step`` metres.

Points are ``lower + i * step`` along each axis (worker frame), indexed in C order (x slowest,
z fastest); a point's coordinates are computed from its integer index, never accumulated, so
no float drift. This is the learner's state space and the landscape's layout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..twin.anthropometry import BodySpec
from ..twin.task import Boundary, TaskSpec, TaskSpecError

DEFAULT_STEP = 0.003  # the paper's action step [m]
BOUNDARY_NAMES = ("body", "paper-code")


def parse_boundary(text: str, body: BodySpec, task: TaskSpec) -> Boundary:
    """``body``, ``paper-code`` or ``X0,X1,Y0,Y1,Z0,Z1`` (worker frame, metres)."""
    if text == "body":
        return Boundary.from_body(body, task)
    if text == "paper-code":
        return Boundary.paper_code()
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != 6:
        raise TaskSpecError(f"boundary = {text!r} is not allowed (use body, paper-code or six "
                            "numbers X0,X1,Y0,Y1,Z0,Z1 in metres)")
    return Boundary(tuple(values[0:2]), tuple(values[2:4]), tuple(values[4:6]))


@dataclass(frozen=True)
class Grid:
    """Every ``step`` metres inside ``boundary``, ends included where they fall on the grid."""

    boundary: Boundary
    step: float = DEFAULT_STEP

    def __post_init__(self):
        if not (math.isfinite(self.step) and self.step > 0):
            raise TaskSpecError(f"step = {self.step!r} is outside the valid range (> 0 m)")
        for axis, (lo, hi) in zip("xyz", (self.boundary.x, self.boundary.y, self.boundary.z),
                                  strict=True):
            if self.step > hi - lo:
                raise TaskSpecError(f"step = {self.step:g} m is larger than the boundary along "
                                    f"{axis} ({hi - lo:g} m)")

    @property
    def shape(self) -> tuple[int, int, int]:
        """Points along x, y, z."""
        return tuple(math.floor((hi - lo) / self.step + 1e-9) + 1
                     for lo, hi in (self.boundary.x, self.boundary.y, self.boundary.z))

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The coordinates along x, y, z [m]."""
        return tuple(lo + np.arange(n) * self.step
                     for lo, n in zip(self.boundary.lower, self.shape, strict=True))

    def points(self, start: int = 0, stop: int | None = None) -> np.ndarray:
        """(n, 3) coordinates of the points with flat indices ``start <= i < stop``."""
        stop = self.size if stop is None else stop
        return self.coordinates(np.arange(start, stop))

    def point(self, flat: int) -> tuple[float, float, float]:
        """The location (x, y, z) [m] of one flat cell."""
        return tuple(float(v) for v in self.coordinates([int(flat)])[0])

    def aligned_block(self, flat: int, edge: int) -> np.ndarray:
        """The flat cells of the aligned cube of ``edge``³ cells that holds cell ``flat``
        (cut at the grid's faces): what a score source evaluates together on a miss."""
        cell = np.unravel_index(int(flat), self.shape)
        ranges = [np.arange(c - c % edge, min(c - c % edge + edge, n))
                  for c, n in zip(cell, self.shape, strict=True)]
        return np.ravel_multi_index(np.meshgrid(*ranges, indexing="ij"), self.shape).ravel()

    def coordinates(self, flat: np.ndarray) -> np.ndarray:
        """(n, 3) coordinates of flat indices."""
        idx = np.stack(np.unravel_index(np.asarray(flat), self.shape), axis=-1)  # (n, 3)
        return self.boundary.lower + idx * self.step

    def nearest_index(self, location) -> np.ndarray:
        """(3,) integer index of the grid point nearest ``location`` (x, y, z) [m]; it lies
        outside ``shape`` when the location is beyond the grid."""
        return np.rint((np.asarray(location, float) - self.boundary.lower) / self.step
                       ).astype(int)

    def nearest_cell(self, location) -> int:
        """The flat index of the grid point nearest ``location`` (x, y, z) [m], which must lie
        within the grid."""
        return int(np.ravel_multi_index(tuple(self.nearest_index(location)), self.shape))

    def describe(self) -> str:
        nx, ny, nz = self.shape
        return (f"grid {nx} x {ny} x {nz} = {self.size:,} points every {self.step * 1000:g} mm "
                f"in boundary '{self.boundary.name}'")
