"""Posture-measurement error as a practical method was measured to make it: a bias and an SD
per joint angle, correlated within a body segment and between the left and right sides.

:class:`~.posture_error.ErrorModel` (the same SD on every angle, independent) is a stress test:
with exactly symmetric postures it makes left and right items disagree as often as they can.
A real instrument errs differently per joint, shares errors between the angles one sensor or
one keypoint feeds, and is biased for some joints. :data:`MEASURED_ERROR` holds a published
comparison of such a method against optical motion capture; :class:`MeasuredError` draws from
it with the same interface as :class:`~.posture_error.ErrorModel` (``errors(n, rng)``), so
every Monte Carlo of the package takes either.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import pandas as pd

from ..errors import ConfigError
from .posture_error import ANGLE_COLUMNS

SEGMENTS = {
    "trunk": ("trunk_flexion", "trunk_side_bend", "trunk_twist"),
    "neck": ("neck_flexion", "neck_side_bend", "neck_twist"),
    "knee": ("knee_flexion",),
    "upper arm": ("upper_arm_flexion", "upper_arm_abduction", "upper_arm_rotation",
                  "shoulder_raise"),
    "elbow": ("elbow_flexion",),
    "wrist": ("wrist_flexion", "wrist_deviation", "wrist_twist"),
}
"""The angles that share a segment's sensor or keypoints (a side's own, for paired angles)."""


def _split(column: str) -> tuple[str, str]:
    """A Posture angle column's side (``""`` for the trunk and neck) and bare angle name."""
    for side in ("left", "right"):
        if column.startswith(f"{side}_"):
            return side, column[len(side) + 1:]
    return "", column


def _segment_of(column: str) -> str:
    """A Posture angle column's segment (without its side)."""
    bare = _split(column)[1]
    for segment, names in SEGMENTS.items():
        if bare in names:
            return segment
    raise ConfigError(f"angle {column!r} belongs to no segment of {sorted(SEGMENTS)}")


SMALLEST_EIGENVALUE = 1e-6
"""A correlation matrix whose smallest eigenvalue is below this is refused: it would tie some
combination of errors to zero (an artefact, not an assumption anyone chose)."""


@dataclass(frozen=True)
class JointError:
    """One angle's error (both sides, for a paired angle): ``bias_deg`` (method less reference)
    and ``sd_deg``; ``read`` says where the figure comes from, or what is assumed."""

    bias_deg: float
    sd_deg: float
    read: str


@dataclass(frozen=True)
class MeasuredError:
    """Gaussian error with a bias and SD per angle, correlated within a segment and between
    sides.

    Attributes:
        name: a short label for tables.
        source: the citation of the comparison the figures come from.
        joints: angle (without its side) -> its :class:`JointError`; every angle column of the
            Posture CSV must be covered (assumptions say so in ``read``).
        within_segment: the correlation of two angles' errors within one segment.
        between_sides: the correlation of one angle's left and right errors.
        scale: every SD multiplied by it (bias kept), for sensitivity runs.
    """

    name: str
    source: str
    joints: dict[str, JointError]
    within_segment: float
    between_sides: float
    scale: float = 1.0
    _chol: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        bare = {c.split("_", 1)[1] if c.startswith(("left_", "right_")) else c
                for c in ANGLE_COLUMNS}
        if missing := sorted(bare - set(self.joints)):
            raise ConfigError(f"measured error {self.name!r} has no figure for {missing}")
        for label, value in (("within_segment", self.within_segment),
                             ("between_sides", self.between_sides)):
            if not -1 < value < 1:
                raise ConfigError(f"{label} = {value!r} is not allowed (a correlation "
                                  "strictly between -1 and 1)")
        corr = self.correlation()
        if np.linalg.eigvalsh(corr).min() < SMALLEST_EIGENVALUE:
            raise ConfigError(f"measured error {self.name!r}: the correlations do not make a "
                              "valid covariance (a combination of errors would be fixed)")
        sd = self.sd()
        cov = corr * np.outer(sd, sd)
        # An angle with no error (SD 0) has a zero row; the factor of its nonzero block serves.
        keep = sd > 0
        chol = np.zeros_like(cov)
        chol[np.ix_(keep, keep)] = np.linalg.cholesky(cov[np.ix_(keep, keep)])
        object.__setattr__(self, "_chol", chol)

    def _joint(self, column: str) -> JointError:
        return self.joints[_split(column)[1]]

    def sd(self) -> np.ndarray:
        """(angles,) each angle column's SD [deg], in :data:`ANGLE_COLUMNS` order."""
        return np.array([self.scale * self._joint(c).sd_deg for c in ANGLE_COLUMNS])

    def bias(self) -> np.ndarray:
        """(angles,) each angle column's bias [deg]."""
        return np.array([self._joint(c).bias_deg for c in ANGLE_COLUMNS])

    def correlation(self) -> np.ndarray:
        """(angles, angles) the errors' correlation matrix, a product of a segment factor and
        a side factor: two angles of one segment correlate ``within_segment`` (1 for an angle
        with itself), two of different segments 0; for two sided angles on opposite sides that
        is multiplied by ``between_sides``. So one angle's left and right errors correlate
        ``between_sides`` and, say, the left arm's flexion and the right arm's abduction their
        product: the Kronecker product of two valid correlation matrices, itself valid."""
        parts = [_split(c) for c in ANGLE_COLUMNS]
        segments = [_segment_of(c) for c in ANGLE_COLUMNS]
        n = len(ANGLE_COLUMNS)
        corr = np.zeros((n, n))
        for i in range(n):
            for j in range(n):
                if segments[i] != segments[j]:
                    continue
                same_angle = parts[i][1] == parts[j][1]
                corr[i, j] = 1.0 if same_angle else self.within_segment
                if parts[i][0] != parts[j][0]:
                    corr[i, j] *= self.between_sides
        return corr

    def errors(self, n: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
        """(n,) float32 error draws [deg] for every angle column (bias included)."""
        block = rng.standard_normal((len(ANGLE_COLUMNS), n), dtype=np.float32)
        drawn = (self._chol.astype(np.float32) @ block
                 + self.bias().astype(np.float32)[:, None])
        return dict(zip(ANGLE_COLUMNS, drawn, strict=True))

    def table(self) -> pd.DataFrame:
        """One row per angle (without its side): bias, SD and where each comes from."""
        return pd.DataFrame([{"angle": k, "bias_deg": j.bias_deg,
                              "sd_deg": self.scale * j.sd_deg, "read": j.read}
                             for k, j in self.joints.items()])


SCHALL_2016 = ("Schall MC, Fethke NB, Chen H, Oyama S, Douphrate DI (2016). Accuracy and "
               "repeatability of an inertial measurement unit system for field-based "
               "occupational studies. Ergonomics 59(4):591-602, doi:10.1080/00140139.2015.1079335")
"""An IMU system against optical motion capture over eight hours of laboratory work: sample-to-
sample RMS differences of 4.1-6.6 deg for the trunk (abstract) and, for the dominant upper arm's
elevation with a complementary filter (its 'Comp-1'), 8.5 deg with mean elevations of 13.2 deg
(IMU) against 13.5 deg (optical) (Table 2)."""
_ARM = JointError(-0.3, 8.5, "Schall et al. 2016, Table 2: upper-arm elevation, Comp-1 "
                  "(RMSD 8.5°; bias = IMU mean 13.2° less optical 13.5°); elevation applied "
                  "to flexion and to abduction")
_TRUNK = JointError(0.0, 6.6, "Schall et al. 2016, abstract: trunk RMSD 4.1–6.6° (the upper "
                    "end); no bias reported, 0 assumed")
_ASSUMED_AXIAL = JointError(0.0, 6.6, "not measured: assumed as the trunk's")
_ASSUMED_LIMB = JointError(0.0, 8.5, "not measured: assumed as the upper arm's")
MEASURED_ERROR = MeasuredError(
    name="IMU (Schall et al. 2016)", source=SCHALL_2016,
    joints={"trunk_flexion": _TRUNK, "trunk_side_bend": _TRUNK,
            "trunk_twist": _ASSUMED_AXIAL, "neck_flexion": _ASSUMED_AXIAL,
            "neck_side_bend": _ASSUMED_AXIAL, "neck_twist": _ASSUMED_AXIAL,
            "knee_flexion": _ASSUMED_LIMB, "upper_arm_flexion": _ARM,
            "upper_arm_abduction": _ARM, "upper_arm_rotation": _ASSUMED_LIMB,
            "shoulder_raise": _ASSUMED_LIMB, "elbow_flexion": _ASSUMED_LIMB,
            "wrist_flexion": _ASSUMED_LIMB, "wrist_deviation": _ASSUMED_LIMB,
            "wrist_twist": _ASSUMED_LIMB},
    within_segment=0.5, between_sides=0.5)
"""The measured error model of the robustness part's headline. Correlations are not reported
by the source (nor by any comparison we could read), so they are assumed: 0.5 between the
angles one segment's sensor feeds, and 0.5 between the two sides of one angle (one
calibration, one filter), their product across both; :data:`MEASURED_VARIANTS` shows what
that assumption and the SDs move. Not modelled: error that depends on the posture (the
source's upper-arm elevation reads 31.6 deg against 35.9 deg optical at the 90th percentile,
Table 2, while the means agree)."""
MEASURED_VARIANTS = {
    "uncorrelated": replace(MEASURED_ERROR, name="IMU, uncorrelated", within_segment=0.0,
                            between_sides=0.0),
    "SDs x0.5": replace(MEASURED_ERROR, name="IMU, SDs ×0.5", scale=0.5),
    "SDs x1.5": replace(MEASURED_ERROR, name="IMU, SDs ×1.5", scale=1.5)}
"""The headline model with its assumed correlations removed, and with every SD halved and
raised by half: a bracket wider than the source's own spread over processing methods (trunk
4.1-6.6 deg, upper arm 7.2-12.1 deg RMS)."""
