"""The study's sections on measured people: how well keypoint formats measure the twin
(``capture``) and the twin beside measured handovers (``people``), with the hashes of what their
results follow from besides their settings (the capture layer's code, the derived figures)."""

from __future__ import annotations

import dataclasses
import hashlib
from pathlib import Path

from ..errors import ConfigError
from ..twin.solver import JOINT_PREFERENCE
from .typed_json import setting


@dataclasses.dataclass(frozen=True)
class CaptureConfig:
    """How well each keypoint format measures the twin (:mod:`..capture_accuracy`): the twin's
    postures at ``postures`` locations drawn (seeded) from the landscape's feasible ones, each
    measured ``draws`` times at every angle error SD of ``angle_sds``: 3.5° for pose models
    trained on ergonomics data (VEHS-7M; Wen et al. 2025), 15° the median RMSE of markerless
    joint angles against optical motion capture (46 people; Wang, Fethke & Baek)."""

    postures: int = setting(1000, lo=1)
    angle_sds: tuple[float, ...] = setting((0.0, 3.5, 15.0), lo=0, unit="deg")
    draws: int = setting(20, lo=1)
    seed: int = setting(40, lo=0)


@dataclasses.dataclass(frozen=True)
class PeopleConfig:
    """The twin beside Kim et al.'s measured handovers (:mod:`..beside_people`): the object
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


def capture_code_version() -> str:
    """A hash of the capture layer's source (the capture part's results follow from it)."""
    from .. import capture

    digest = hashlib.sha256()
    for path in sorted(Path(capture.__file__).parent.glob("*.py")):
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]
