"""The study's section ``sensitivity``: a landscape per modelling variant."""

from __future__ import annotations

import dataclasses

from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class SensitivityConfig:
    step: float = setting(0.01, positive=True, unit="m")
