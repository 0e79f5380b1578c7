"""The study's section ``population``: the sampled workforce and its one-size location."""

from __future__ import annotations

import dataclasses

from ..choices import BOUNDARIES, DEFAULT_WORKER, WORKERS
from ..typed_json import setting
from ..workforce import Workforce, workforce_of


@dataclasses.dataclass(frozen=True)
class PopulationConfig:
    size: int = setting(Workforce.size, lo=1)
    seed: int = setting(Workforce.seed, lo=0)
    female_share: float = setting(Workforce.female_share, lo=0, hi=1)
    reference: str = setting(DEFAULT_WORKER, choices=WORKERS)
    boundary: str = setting("paper-code", choices=BOUNDARIES)
    step: float = setting(0.01, positive=True, unit="m")
    bootstrap: int = setting(2000, lo=1)
    bootstrap_seed: int = setting(7, lo=0)

    def workers(self):
        """The population's workers and, last, its reference worker (a table:
        :func:`..workforce.workforce_of`)."""
        return workforce_of(Workforce(self.size, self.seed, self.female_share), self.reference)
