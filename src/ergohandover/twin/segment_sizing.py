"""A twin sized from segment lengths measured by keypoints, not from stature and sex alone.

Keypoint trackers give joint-centre distances (hip to knee, elbow to wrist), not the survey's
landmark heights. :func:`body_from_segments` turns the lengths into the landmarks the twin
derives those segments from, and lets the survey's body model fill in the rest.
"""

from __future__ import annotations

from collections.abc import Mapping

from .anthropometry import BodySpec, BodySpecError, landmarks_of

SEGMENTS = ("thigh", "shank", "upper_arm", "forearm")
"""The joint-centre segments :func:`body_from_segments` takes: hip to knee, knee to ankle,
shoulder to elbow and elbow to wrist joint."""
SEGMENT_RANGE_M = (0.05, 1.0)
SETTLING_ROUNDS = 4


def body_from_segments(lengths: Mapping[str, float], sex: str = "male",
                       **given: float) -> BodySpec:
    """A body whose joint-centre segments are ``lengths`` [m] (any of :data:`SEGMENTS`), with
    ``given`` any measurements known besides (``stature_m``, ``shoulder_height_m``, ...).

    Each length sets the landmark the twin derives that segment from (knee and hip height,
    upper-arm length, wrist height) above the ankle or below the shoulder. Those two anchors
    are the body model's given the rest, settled over a few rounds (longer legs make a taller
    body) and then held, so the twin's segments equal ``lengths`` to 0.1 mm and everything
    else is the model's mean given them.

    Raises:
        BodySpecError: an unknown segment, a length outside 0.05-1 m, or lengths that do not
            fit one body; one line.
    """
    unknown = sorted(set(lengths) - set(SEGMENTS))
    if unknown:
        raise BodySpecError(f"segment {unknown[0]!r} is not known; the known ones are "
                            f"{', '.join(SEGMENTS)}")
    lo, hi = SEGMENT_RANGE_M
    for name, value in lengths.items():
        if not lo <= value <= hi:
            raise BodySpecError(f"{name} = {value!r} is outside the valid range {lo:g}-{hi:g} m")
    base = landmarks_of(BodySpec.from_measurements(given, sex))
    for round_ in range(SETTLING_ROUNDS):
        ankle = given.get("ankle_height_m", base["ankle_height_m"])
        shoulder = given.get("shoulder_height_m", base["shoulder_height_m"])
        measured = dict(given)
        if round_ == SETTLING_ROUNDS - 1:  # the last round holds the anchors
            measured.update(ankle_height_m=ankle, shoulder_height_m=shoulder)
        knee = ankle + lengths.get("shank", base["knee_height_m"] - ankle)
        measured["knee_height_m"] = knee
        if "thigh" in lengths:
            measured["hip_height_m"] = knee + lengths["thigh"]
        upper = lengths.get("upper_arm", base["upper_arm_length_m"])
        measured["upper_arm_length_m"] = upper
        if "forearm" in lengths:
            measured["wrist_height_m"] = shoulder - upper - lengths["forearm"]
        measured = {name: round(value, 4) for name, value in measured.items()}
        base = landmarks_of(BodySpec.from_measurements(measured, sex))
    return BodySpec.from_measurements(measured, sex)
