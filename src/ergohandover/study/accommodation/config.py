"""The study's section ``accommodation``: the workforce's accommodation zone."""

from __future__ import annotations

import dataclasses

from ...landscape.grid import BOUNDARY_NAMES
from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class AccommodationConfig:
    """A workforce of ``size`` drawn from the survey's body model, each worker solved at every
    ``step`` of the boundary; acceptable means REBA <= ``reba_max`` and RULA <= ``rula_max``
    (defaults: REBA's negligible-or-low risk, RULA's action levels 1-2, below where either
    method calls for change), measured ``draws`` times per location under the measured error
    model; the zone serves ``share`` of the workforce."""

    size: int = setting(1000, lo=1)
    seed: int = setting(2031, lo=0)
    female_share: float = setting(0.5, lo=0, hi=1)
    boundary: str = setting("paper-code", choices=BOUNDARY_NAMES)
    step: float = setting(0.03, positive=True, unit="m")
    reba_max: int = setting(3, lo=1, hi=15)
    rula_max: int = setting(4, lo=1, hi=7)
    share: float = setting(0.9, lo=0, hi=1)
    draws: int = setting(16, lo=1)
    error_seed: int = setting(13, lo=0)
    bootstrap: int = setting(1000, lo=1)
    bootstrap_seed: int = setting(17, lo=0)
