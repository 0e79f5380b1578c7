"""The study's section ``robustness``: the recommendation under posture error and a wrong
model."""

from __future__ import annotations

import dataclasses

from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class RobustnessConfig:
    draws: int = setting(4000, lo=1)
    seed: int = setting(11, lo=0)
    angle_sds: tuple[float, ...] = setting((0.0, 1.0, 2.0, 5.0, 10.0), lo=0, unit="deg")
    robust_sd: float = setting(5.0, positive=True, unit="deg")
    # How far above the error-free optimum a location may score and still be a candidate for
    # the robust location "among optima" (the one that does not trade the worker's posture).
    robust_tolerance: int = setting(0, lo=0)
    structure: str = setting("independent", choices=("independent", "bilateral"))
    placement_radii_cm: tuple[float, ...] = setting((0.57, 1.0, 2.0, 5.0), positive=True,
                                                    unit="cm")
    stride: int = setting(3, lo=1)
    screen_draws: int = setting(128, lo=1)
    keep: int = setting(32, lo=1)
    radius: int = setting(2, lo=0)
    worker_draws: int = setting(1000, lo=1)
    worker_stride: int = setting(2, lo=1)
    # Each resample and split re-chooses the one-size cells over every worker's grid (0.1 s).
    resamples: int = setting(300, lo=1)
    splits: int = setting(150, lo=1)
