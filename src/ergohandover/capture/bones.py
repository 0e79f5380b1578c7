"""Does a keypoint file fit the format it is declared in? Its bones, measured as that format's
joints, must have a person's proportions.

A file of 17 points in COCO's order read as Human3.6M's takes the eyes for a hip and a knee and
the hips for a shoulder and an elbow: every later check may still pass after some ``--up`` or
``--units``, and the scores are wrong without a word. Bones keep their length in any posture,
whatever the unit and whichever axis is up, so their ratios tell a wrong joint order before
anything else is checked: each bone (thigh, shank, upper arm, forearm; the shoulder and hip
widths) against the worker twin's, after one common scale, and each left bone against its
right. A file that fails is told which format of the same joint count its bones fit.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .formats import FORMATS, KeypointFormat
from .readers import KeypointFileError, Keypoints

BONES = {  # bone -> (landmark, landmark, the twin's segment of the same span)
    **{f"{side}_{bone}": (f"{side}_{a}", f"{side}_{b}", segment)
       for side in ("left", "right")
       for bone, a, b, segment in (("thigh", "hip", "knee", "thigh_length"),
                                   ("shank", "knee", "ankle", "shank_length"),
                                   ("upper_arm", "shoulder", "elbow", "upper_arm_length"),
                                   ("forearm", "elbow", "wrist", "forearm_length"))},
    "shoulder_width": ("left_shoulder", "right_shoulder", "shoulder_width"),
    "hip_width": ("left_hip", "right_hip", "hip_width"),
}
"""The bones measured, each between two landmarks every keypoint format gives."""
SPREAD = 2.0
"""How much the bones' ratios to the twin's may differ (the largest over the smallest, the
shoulder width among them): people differ by far less (ANSUR II's 5th- and 95th-percentile
limbs are within 1.25 of the 50th's proportions, a child's within some 1.3 of an adult's, a
pose estimator's lifted bones err by up to some 20 %), a joint taken for another by far more
(an eye for a knee makes a thigh a tenth of a person's; an ankle for a shoulder, an upper arm
of three)."""
WIDTH_FACTOR = 2.5
"""How far the hip width may be from the twin's after the scale the other bones give: formats
place the hip points differently (COCO's on the skin over the greater trochanter, about 1.5
times the joint centres' width)."""
SIDE_FACTOR = 1.5
"""How much longer a left bone may be than its right or the reverse (a person's differ by a few
per cent, a pose estimator's lifted bones by up to some 20 %)."""
MIN_BONES = 4
"""Bones needed to tell a fit (a file missing most points is not judged)."""


@lru_cache(maxsize=1)
def template() -> dict[str, float]:
    """Each bone's length in the worker twin (ANSUR II's 50th-percentile man) [m]."""
    from ..twin.anthropometry import BodySpec

    segments = BodySpec().segments()
    return {bone: float(getattr(segments, segment)) for bone, (_, _, segment) in BONES.items()}


def bone_lengths(points: np.ndarray, fmt: KeypointFormat) -> dict[str, float]:
    """Each bone's median length over frames, ``points`` (N, J, 3) read as ``fmt``'s joints;
    bones missing in every frame are left out."""
    marks = fmt.landmarks

    def at(mark: str) -> np.ndarray:
        return points[:, [fmt.index(j) for j in marks[mark]]].mean(axis=1)

    out = {}
    for bone, (a, b, _) in BONES.items():
        if a in marks and b in marks:
            length = np.linalg.norm(at(a) - at(b), axis=1)
            if np.isfinite(length).any():
                out[bone] = float(np.nanmedian(length))
    return out


def misfit(lengths: dict[str, float]) -> tuple[float, str]:
    """How far bones are from a person's: the worst of their spread over :data:`SPREAD`, the
    hip width's factor over :data:`WIDTH_FACTOR` and each left-right factor over
    :data:`SIDE_FACTOR` (above 1: not a person's); and that worst one described (NaN and ""
    when fewer than :data:`MIN_BONES` are seen)."""
    if len(lengths) < MIN_BONES:
        return np.nan, ""
    twin = template()
    # A bone of zero length (two joints on one point) is as far from a person's as can be.
    ratio = {bone: max(length, 1e-9) / twin[bone] for bone, length in lengths.items()}
    limbs = {bone: r for bone, r in ratio.items() if bone != "hip_width"}
    low, high = min(limbs, key=limbs.get), max(limbs, key=limbs.get)
    spread = limbs[high] / limbs[low]
    found = [(spread / SPREAD, f"its {_name(high)} is {spread:.2g} times too long for its "
              f"{_name(low)}, against a person's proportions")]
    if "hip_width" in ratio:
        # Scaled as the limbs' middle: the geometric mean of their extremes.
        factor = ratio["hip_width"] / np.sqrt(limbs[low] * limbs[high])
        found.append((max(factor, 1 / factor) / WIDTH_FACTOR,
                      f"its hip width is {factor:.2g} times a person's for its limbs"))
    for bone in (b.removeprefix("left_") for b in lengths if b.startswith("left_")):
        if f"right_{bone}" in ratio:
            factor = ratio[f"left_{bone}"] / ratio[f"right_{bone}"]
            found.append((max(factor, 1 / factor) / SIDE_FACTOR,
                          f"its left {_name(bone)} is {factor:.2g} times its right"))
    return max(found)


def _name(bone: str) -> str:
    return bone.replace("_", " ")


def check_format(kp: Keypoints, what: str, flag: str = "--format {}") -> None:
    """Refuse keypoints whose bones, read as ``kp.fmt``'s joints, are not a person's, naming
    the formats of the same joint count they fit (one-line :class:`KeypointFileError`); run
    before the unit, size and up-axis checks, so that none of them names a flag that would only
    make a wrong joint order score. ``flag``: how the user names a format (``{}`` its name).
    Files with too few points seen to tell pass."""
    fmt = kp.fmt
    if fmt.name not in FORMATS:  # a BVH file's joints come by name from its own hierarchy
        return
    off, said = misfit(bone_lengths(kp.points, fmt))
    if not off > 1.0:
        return
    others = [f.name for f in FORMATS.values()
              if f.name != fmt.name and len(f.joints) == len(fmt.joints)]
    fits = [name for name in others
            if misfit(bone_lengths(kp.points, FORMATS[name]))[0] <= 1.0]
    given = flag.format(fmt.name)
    if fits:
        raise KeypointFileError(f"{what}: its bones fit {' and '.join(fits)}, not {given} "
                                f"({said}): try {flag.format(fits[0])}")
    nor = f", nor {' or '.join(others)}" if others else ""
    raise KeypointFileError(f"{what}: its bones do not fit {given} ({said}){nor}: give its "
                            f"joints in {fmt.name}'s order (docs/capture.md), or the format "
                            "they are in")
