"""The study's section ``people``: the twin beside measured handovers, and the hash of the
derived figures its results follow from."""

from __future__ import annotations

import dataclasses
import hashlib

from ...errors import ConfigError
from ...twin.solver import JOINT_PREFERENCE
from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class PeopleConfig:
    """The twin beside Kim et al.'s measured handovers (:mod:`.beside_people`): the object
    the twin holds (the data set does not name it: a light one of ``OBJECTS``); the fit of
    ``fit_weights`` (factors on joint preferences, ``gaze`` on the gaze weight) by at most
    ``fit_evaluations`` evaluations on ``train_share`` of the in-distribution recordings (seeded
    split); the one-handed optimum of the median receiver's twin every ``step`` inside
    ``boundary`` (worker frame X0,X1,Y0,Y1,Z0,Z1, the right hand's side)."""

    object: str = setting("bottle", choices=("bottle", "baton", "box"))
    train_share: float = setting(0.5, lo=0.1, hi=0.9)
    fit_weights: tuple[str, ...] = setting(("lumbar_flexion", "neck_flexion",
                                            "shoulder_flexion", "shoulder_abduction",
                                            "elbow_flexion", "gaze"))
    fit_evaluations: int = setting(80, lo=1)
    step: float = setting(0.01, positive=True, unit="m")
    boundary: str = setting("-0.2,0.7,0.6,1.7,0.0,0.7")
    seed: int = setting(41, lo=0)

    def __post_init__(self):
        allowed = ("gaze", *JOINT_PREFERENCE)
        for name in self.fit_weights:
            if name not in allowed:
                raise ConfigError(f"people.fit_weights: {name!r} is not allowed (use "
                                  f"{', '.join(allowed)})")


def measured_data_version() -> str:
    """A hash of the derived figures of the measured handovers (the people part reads them)."""
    from .beside_people import MEASURED

    return hashlib.sha256(MEASURED.read_bytes()).hexdigest()[:16]
