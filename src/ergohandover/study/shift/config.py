"""The study's section ``shift``: joint fatigue over a working day of handovers, and the hash
of the fatigue models' code its results follow from."""

from __future__ import annotations

import dataclasses
import hashlib
from pathlib import Path

from ..typed_json import setting


@dataclasses.dataclass(frozen=True)
class ShiftConfig:
    """The fatigue model checked against the published endurance times: each joint's endurance
    time at every sustained load of ``reference_loads`` (shares of strength) from the model's
    closed form beside the power law's, and both as curves every ``curve_step`` from
    ``curve_step`` to 1."""

    reference_loads: tuple[float, ...] = setting((0.1, 0.2, 0.3, 0.4, 0.5), lo=0, hi=1)
    curve_step: float = setting(0.01, lo=0.001, hi=0.5)


def fatigue_code_version() -> str:
    """A hash of the fatigue models' source (the shift part's results follow from it)."""
    from ...workload import fatigue, lifft

    digest = hashlib.sha256()
    for module in (fatigue, lifft):
        path = Path(module.__file__)
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]
