"""Keypoints checked before they are scored: every frame has a point, no point is infinite, a
missing point is refused or declared unseen, and the body is the size of a person and upright
along the stated up axis (a file in centimetres, or with another axis up, is caught here)."""

from __future__ import annotations

import numpy as np

from .formats import UP_AXES, KeypointFormat, z_up
from .readers import KeypointFileError, Keypoints, unit_scale

MISSING = ("error", "unseen")
"""What a missing point does (:func:`check_keypoints`)."""

MIN_HEIGHT_M, MAX_HEIGHT_M = 0.3, 3.0
"""The body's extent along the up axis that a file in metres gives (median over frames)."""
TYPICAL_HEIGHT_M = 1.7
"""A standing adult's extent along the up axis, for the hint of which unit fits a file: between
ANSUR II's 50th-percentile woman and man (1.63 and 1.76 m stature); the hint is approximate by
design."""

CANDIDATE_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "inch": 0.0254,
                   "CMU's 1/0.45 inch": 0.0254 / 0.45}
"""Units a file may be in, as the metres one unit is: SI's, inches, and the CMU motion-capture
database's (its BVH files' unit, 1/0.45 inch)."""
LEG_M = (0.55, 1.15)
"""A person's leg, hip joint to knee to ankle [m]: from a short woman's (about 0.66 m at
1.50 m stature) to a tall man's (about 0.98 m at 2.0 m), widened so that a leg bent in a
crouch still fits; the units' ratios (at least 2.2 between neighbours) exceed the range's
(2.1), so at most one unit fits."""

MAX_LYING_RATIO = 1.5
"""A body whose horizontal extent is more than this many times its extent along the up axis
lies across it: the up axis is wrong."""


def _outside(height: float) -> str:
    """``height`` with the digits that keep it outside the allowed range as printed (0.2999 is
    not shown as 0.3, which the message says is allowed)."""
    for digits in range(3, 10):
        shown = f"{height:.{digits}g}"
        if not MIN_HEIGHT_M <= float(shown) <= MAX_HEIGHT_M:
            return shown
    return repr(height)


def _flip(up: str) -> str:
    return up[1:] if up.startswith("-") else f"-{up}"


def check_keypoints(kp: Keypoints, up: str, missing: str, what: str,
                    units: str = "m") -> np.ndarray:
    """Check keypoints before they are scored.

    Args:
        kp: the file's keypoints.
        up: the up axis of ``kp.points`` (``x``, ``-y``, ...).
        missing: ``error`` (a missing point is an error) or ``unseen`` (the columns the missing
            points decide are unseen in their frames).
        what: the file's name as the user typed it (messages start with it).
        units: the unit the file was read in (a body of the wrong size is told the unit that
            would fit it).

    Returns:
        (N,) bool: the frames with a missing (NaN) point.

    Raises:
        KeypointFileError: one line, in this order: no frames; an infinite coordinate; a frame
        without any point; a missing point with ``missing="error"``; a body whose median extent
        along the up axis is outside 0.3-3 m; a body lying across the up axis; a body upside
        down along it. The body's extent is that of the format's ``body`` joints (a BVH file's
        props do not make it tall).
    """
    if missing not in MISSING:
        raise KeypointFileError(f"{what}: --missing {missing!r} is not allowed (use "
                                f"{' or '.join(MISSING)})")
    order, sign = z_up(up)  # the one rule of an up axis: FormatError for another
    points, joints, frames = kp.points, kp.fmt.joints, kp.frames
    if len(points) == 0:
        raise KeypointFileError(f"{what} has no frames")
    infinite = np.argwhere(np.isinf(points).any(axis=2))
    if infinite.size:
        i, j = infinite[0]
        raise KeypointFileError(f"{what}: frame {frames[i]}, joint '{joints[j]}' has an infinite "
                                f"coordinate (expected finite numbers; NaN or an empty cell for "
                                f"a missing point)")
    absent = np.isnan(points).any(axis=2)  # (N, J)
    empty = np.flatnonzero(absent.all(axis=1))
    if empty.size:
        raise KeypointFileError(f"{what}: frame {frames[empty[0]]} has no points (every joint is "
                                f"missing; {empty.size} such frame(s)): remove such frames")
    gaps = absent.any(axis=1)
    if missing == "error" and gaps.any():
        i, j = np.argwhere(absent)[0]
        raise KeypointFileError(
            f"{what}: frame {frames[i]}, joint '{joints[j]}' is missing (NaN or an empty cell; "
            f"{int(gaps.sum())} of {len(gaps)} frames miss points): --missing unseen scores such "
            f"frames with the columns those points decide as unseen")
    p = points[..., order] * np.array([1.0, 1.0, sign])  # z up
    body = p[:, [kp.fmt.index(j) for j in kp.fmt.body]] if kp.fmt.body else p
    extent = np.nanmax(body, axis=1) - np.nanmin(body, axis=1)  # (N, 3)
    height = float(np.median(extent[:, 2]))
    axis = up.lstrip("-")
    if not MIN_HEIGHT_M <= height <= MAX_HEIGHT_M:
        # What one file unit would be for a body of typical height: the --units that fits.
        per_unit = TYPICAL_HEIGHT_M / height / unit_scale(units, what)
        hint = (f"is the up axis right (--up), and what is the file's unit? A "
                f"{TYPICAL_HEIGHT_M:g} m body would make one unit {per_unit:.3g} m "
                f"(--units {per_unit:.3g}; m, cm and mm are 1, 0.01 and 0.001)")
        raise KeypointFileError(
            f"{what}: the body is {_outside(height)} m tall read as --units {units} (the median "
            f"extent of its points along the up axis {axis}): expected {MIN_HEIGHT_M:g}-"
            f"{MAX_HEIGHT_M:g} m; {hint}")
    across = float(np.median(extent[:, :2].max(axis=1)))
    if across > MAX_LYING_RATIO * height:
        raise KeypointFileError(
            f"{what}: the body lies across the up axis '{up}' (a median {across:.2f} m across "
            f"it and {height:.2f} m along it): give the axis that points up "
            f"(--up {'|'.join(UP_AXES)})")
    marks = kp.fmt.landmarks
    needed = ("left_shoulder", "right_shoulder", "left_ankle", "right_ankle")
    if all(m in marks for m in needed):
        def level(mark: str) -> np.ndarray:
            return p[:, [kp.fmt.index(j) for j in marks[mark]], 2].mean(axis=1)

        rise = ((level("left_shoulder") + level("right_shoulder"))
                - (level("left_ankle") + level("right_ankle"))) / 2
        seen = rise[np.isfinite(rise)]
        if seen.size and float(np.median(seen)) < 0:
            raise KeypointFileError(
                f"{what}: the body is upside down along the up axis '{up}' (its shoulders are "
                f"a median {-float(np.median(seen)):.2f} m below its ankles): is the up axis "
                f"'{_flip(up)}'? (--up)")
    return gaps


def leg_lengths(points: np.ndarray, fmt: KeypointFormat) -> list[np.ndarray]:
    """Per side the format gives a hip, knee and ankle of, each frame's hip-to-knee plus
    knee-to-ankle (N,) in the file's unit."""
    marks = fmt.landmarks

    def at(mark: str) -> np.ndarray:
        return points[:, [fmt.index(j) for j in marks[mark]]].mean(axis=1)  # (N, 3)

    legs = []
    for side in ("left", "right"):
        hip, knee, ankle = (f"{side}_{part}" for part in ("hip", "knee", "ankle"))
        if all(m in marks for m in (hip, knee, ankle)):
            legs.append(np.linalg.norm(at(hip) - at(knee), axis=1)
                        + np.linalg.norm(at(knee) - at(ankle), axis=1))
    return legs


def leg_length(kp: Keypoints) -> float:
    """The median over frames and sides of hip-to-knee plus knee-to-ankle, in the file's unit
    (NaN where the format gives no hip, knee or ankle): bones keep their length whatever the
    posture and whichever axis is up."""
    legs = leg_lengths(kp.points, kp.fmt)
    found = np.concatenate(legs) if legs else np.array([np.nan])
    return float(np.nanmedian(found)) if np.isfinite(found).any() else float("nan")


def infer_unit(kp: Keypoints, what: str) -> tuple[str, float]:
    """The unit of keypoints read in the file's own unit, from the length of their legs: the
    one of :data:`CANDIDATE_UNITS` that makes the legs a person's (:data:`LEG_M`). Returns its
    name and the metres one file unit is; a one-line KeypointFileError naming ``--units`` when
    none does (or the format gives no legs)."""
    leg = leg_length(kp)
    if not np.isfinite(leg) or leg <= 0:
        raise KeypointFileError(f"{what}: its unit cannot be told (the file gives no hip, knee "
                                "and ankle to measure a leg by): give --units")
    fits = [(name, metres) for name, metres in CANDIDATE_UNITS.items()
            if LEG_M[0] <= leg * metres <= LEG_M[1]]
    if len(fits) != 1:
        raise KeypointFileError(
            f"{what}: its unit cannot be told: its legs are {leg:.3g} file units long (hip to "
            f"knee to ankle), which no unit of {', '.join(CANDIDATE_UNITS)} makes a person's "
            f"{LEG_M[0]:g}-{LEG_M[1]:g} m: give --units (m, cm, mm, or the metres one unit is)")
    return fits[0]
