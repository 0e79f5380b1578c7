"""What no REBA or RULA source fixes, held in one frozen settings object.

Hignett & McAtamney (2000) and McAtamney & Corlett (1993) are worksheets for an observer: they
do not say how far from vertical a trunk may be and still be "upright", which band an angle
exactly on an edge belongs to, or from what angle a twist, side bend, abduction, rotation,
shoulder raise or wrist deviation/twist "counts". An automated scorer must choose; these are
the choices, each overridable (``ergohandover score --help``).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import ConfigError
from ..ranges import check_ranges, ranged

MAX_COUNT_FROM_DEG = 30.0
MAX_NEUTRAL_TOLERANCE_DEG = 15.0


class SettingsError(ConfigError):
    """A scoring setting outside its valid range; the message is one line."""


@dataclass(frozen=True)
class ScoringSettings:
    """Choices the REBA and RULA sources leave open. Angles in [deg].

    Defaults: the observer's usual reading of the worksheets. A 5° neutral tolerance is the
    resolution of a goniometer read by eye; 10° for trunk/neck twist and side bend and wrist
    deviation is the smallest deviation an observer reliably sees; 20° for abduction and
    rotation mirrors the worksheet's own 20° flexion band for the upper arm; 10° of clavicle
    elevation above its resting slope is a visibly raised shoulder (a depressed one is never
    raised); 30° of forearm rotation from mid-position is a third of its range. An angle
    exactly on a band edge falls in the less severe band, as the worksheets' wording "0–20°"
    then ">20°" reads. The trunk/neck +1 for twist or side bend is
    given once (the original paper) rather than once for each.
    """

    neutral_tolerance_deg: float = ranged(
        5.0, "half-width of 'upright'/'neutral' for trunk, neck and wrist (0-15)", 0.0,
        MAX_NEUTRAL_TOLERANCE_DEG, "deg")
    band_edge: str = ranged(
        "lower", "band for an angle exactly on a band edge: the 'lower' (less severe) or "
        "'upper' (more severe) one", choices=("lower", "upper"))
    twist_from_deg: float = ranged(
        10.0, "trunk/neck twist counts beyond this (0-30)", 0.0, MAX_COUNT_FROM_DEG, "deg")
    side_bend_from_deg: float = ranged(
        10.0, "trunk/neck side bend counts beyond this (0-30)", 0.0, MAX_COUNT_FROM_DEG, "deg")
    abduction_from_deg: float = ranged(
        20.0, "upper-arm abduction counts beyond this (0-30)", 0.0, MAX_COUNT_FROM_DEG, "deg")
    rotation_from_deg: float = ranged(
        20.0, "upper-arm rotation counts beyond this (0-30)", 0.0, MAX_COUNT_FROM_DEG, "deg")
    shoulder_raise_from_deg: float = ranged(
        10.0, "shoulder elevation counts beyond this (0-30)", 0.0, MAX_COUNT_FROM_DEG, "deg")
    wrist_deviation_from_deg: float = ranged(
        10.0, "wrist deviation counts beyond this (0-30)", 0.0, MAX_COUNT_FROM_DEG, "deg")
    wrist_twist_from_deg: float = ranged(
        30.0, "wrist twist counts (REBA) / is near end of range (RULA) beyond this (0-30)",
        0.0, MAX_COUNT_FROM_DEG, "deg")
    twist_side_bend_rule: str = ranged(
        "single", "REBA trunk/neck: 'single' +1 if twisted or side-bent (original), or "
        "'each' +1 for each", choices=("single", "each"))

    def __post_init__(self):
        check_ranges(self, SettingsError)

    @property
    def severe_on_edge(self) -> bool:
        """True when an angle exactly on a band edge takes the more severe band."""
        return self.band_edge == "upper"
