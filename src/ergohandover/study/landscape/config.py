"""The study's section ``landscape``: the default worker's exhaustive landscape."""

from __future__ import annotations

import dataclasses

from ...landscape.grid import DEFAULT_STEP
from ..choices import BOUNDARIES, GAZES
from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class LandscapeVariants:
    """The landscape's statistics under each boundary and gaze setting, on a coarser grid."""

    boundaries: tuple[str, ...] = setting(("paper-code", "body"), choices=BOUNDARIES)
    gaze: tuple[str, ...] = setting(("on", "off"), choices=GAZES)
    step: float = setting(0.01, positive=True, unit="m")


@dataclasses.dataclass(frozen=True)
class LandscapeConfig:
    """The default worker's exhaustive landscape: the paper's grid (paper-code boundary, 3 mm)."""

    boundary: str = setting("paper-code", choices=BOUNDARIES)
    step: float = setting(DEFAULT_STEP, positive=True, unit="m")
    gaze: str = setting("on", choices=GAZES)
    variants: LandscapeVariants = setting(LandscapeVariants())
