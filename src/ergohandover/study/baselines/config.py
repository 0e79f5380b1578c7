"""The study's section ``baselines``: the paper's comparison from its five starts."""

from __future__ import annotations

import dataclasses

from ..learning.config import LearnedLocation
from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class BaselinesConfig:
    render: bool = setting(True)
    seed: int = setting(0, lo=0)
    other_starts: int = setting(5, lo=0)
    starts_seed: int = setting(2026, lo=0)
    reach: dict[str, float] = setting({"paper-code": 0.04, "body": 0.05}, positive=True,
                                      unit="m")
    location: LearnedLocation = setting(LearnedLocation())
