"""The study's section ``validation``: the twin beside published human data."""

from __future__ import annotations

import dataclasses

from ...envs.scores import OBJECTIVES
from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class ValidationConfig:
    optimum_of: str = setting("paper_postural", choices=OBJECTIVES)
