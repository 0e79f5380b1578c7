"""The study's section ``participants``: the simulated VR participants."""

from __future__ import annotations

import dataclasses

from ..choices import WORKERS
from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class ParticipantsConfig:
    workers: tuple[str, ...] = setting(("p5-female", "p50-female", "p95-female", "p5-male",
                                        "p50-male", "p95-male"), choices=WORKERS)
    step: float = setting(0.006, positive=True, unit="m")
