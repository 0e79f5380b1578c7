"""The study's section ``manikins``: the lifting task every workload figure of the study
assumes."""

from __future__ import annotations

import dataclasses

from ...workload.lifting import DURATIONS, LiftTask
from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class ManikinsConfig:
    """The lifting task every workload figure of the study assumes (docs/workload.md)."""

    lift_frequency: float = setting(LiftTask.lift_frequency, lo=0, hi=15, unit="lifts/min")
    lift_duration: str = setting(LiftTask.lift_duration, choices=DURATIONS)
    lift_destination: float = setting(LiftTask.lift_destination, lo=0, hi=1.75, unit="m")

    def lift(self) -> LiftTask:
        return LiftTask(self.lift_frequency, self.lift_duration, self.lift_destination)
