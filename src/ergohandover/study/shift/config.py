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
    ``curve_step`` to 1; and the default worker's shift at every location of the population's
    grid, at each rate and hold (each pair whose hold fits in its cycle). The accommodation
    part reads the same shifts and ``keep`` for its workforce."""

    reference_loads: tuple[float, ...] = setting((0.1, 0.2, 0.3, 0.4, 0.5), lo=0, hi=1)
    curve_step: float = setting(0.01, lo=0.001, hi=0.5)
    # The default worker's shift at every location of the population's grid: handovers a
    # minute and seconds each is held (a handover every minute, to one every 10 s; a quick
    # hand-off and a 10 s hold while the worker takes the box), over an 8-hour shift.
    rates_per_min: tuple[float, ...] = setting((1.0, 2.0, 4.0, 6.0), positive=True)
    holds_s: tuple[float, ...] = setting((3.0, 8.0), positive=True, unit="s")
    hours: float = setting(8.0, positive=True, unit="h")
    # What a worker should keep of every joint's capacity at the shift's end, for the
    # workforce's share (the accommodation part's workers): four fifths, an assumption of this
    # study (no published limit on end-of-shift capacity is known to it), so that a worker ends
    # the day with most of each joint's strength left for what else the job asks.
    keep: float = setting(0.8, lo=0, hi=1)

    def plans(self):
        """Each rate and hold whose hold fits in its cycle, as a shift of ``hours``."""
        from ...workload.fatigue import Shift

        return [Shift(rate, hold, self.hours) for rate in self.rates_per_min
                for hold in self.holds_s if hold < 60.0 / rate]


def fatigue_code_version() -> str:
    """A hash of the fatigue models' source and of the joint loads they read (the shift
    part's results and the accommodation part's workforce shifts follow from it)."""
    from ...workload import back, fatigue, lifft, strength

    digest = hashlib.sha256()
    for module in (fatigue, lifft, strength, back):
        path = Path(module.__file__)
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]
