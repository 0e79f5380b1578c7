"""The study's section ``ablations``: human IK, the twin's solver against PyBullet's."""

from __future__ import annotations

import dataclasses

from ..choices import BOUNDARIES
from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class AblationsConfig:
    ik_boundary: str = setting("paper-code", choices=BOUNDARIES)
    ik_step: float = setting(0.015, positive=True, unit="m")
