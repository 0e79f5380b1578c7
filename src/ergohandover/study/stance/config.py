"""The study's section ``stance``: the headline comparison for a worker who may step."""

from __future__ import annotations

import dataclasses

from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class StanceConfig:
    """The headline comparisons for a worker who may step toward the box (the task's stance
    ``step``) beside the planted one: the stepping worker's own landscape every ``step`` on the
    landscape's boundary, and the comparisons under posture error (``angle_sds``, ``draws``
    measurements each, seeded)."""

    step: float = setting(0.01, positive=True, unit="m")
    angle_sds: tuple[float, ...] = setting((0.0, 5.0), lo=0, unit="deg")
    draws: int = setting(4000, lo=1)
    seed: int = setting(27, lo=0)
