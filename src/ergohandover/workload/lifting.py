"""The revised NIOSH lifting equation (Waters, Putz-Anderson, Garg & Fine 1993, *Ergonomics*
36:749-776), as its Applications Manual states it (Waters, Putz-Anderson & Garg 1994, DHHS
(NIOSH) Publication 94-110, revised 2021; its formulas and tables read as transcribed twice,
independently, in the public repository nbarr1/ErgonomicTool, docs/methods/rnle.md):

    RWL = LC x HM x VM x DM x AM x FM x CM,   LI = load / RWL

with LC = 23 kg; HM = 25/H (H in cm, at least 25; 0 beyond 63); VM = 1 - 0.003 |V - 75|
(0 beyond 175 cm); DM = 0.82 + 4.5/D (D at least 25; 0 beyond 175 cm); AM = 1 - 0.0032 A
(0 beyond 135°); FM from the manual's Table 5 (interpolated linearly between its rows, as
the manual prescribes; a frequency below 0.2 lifts/min counts as 0.2, one above a column's
last nonzero row gives 0); CM from its Table 7.

A handover is a lift's origin: the worker takes the box at the handover location and sets it
down at the task's destination height. H is the hands' horizontal distance from the point
midway between the ankles (the worker frame's origin), V their height, D the vertical travel
to the destination, A the angle of the hands from the mid-sagittal plane, all at the origin
(the manual evaluates the destination too only where the worker must control the box
there). The equation's stated limits hold here too: two hands, standing, smooth lifting,
a stable object, good footing and a moderate climate (manual, p. 6).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..errors import ConfigError
from ..ranges import check_ranges, ranged

DURATIONS = ("short", "moderate", "long")
"""Work duration: up to 1 h, up to 2 h (each followed by enough recovery, manual pp. 13-14),
up to 8 h."""
COUPLINGS = ("good", "fair", "poor")

FREQUENCIES = np.array([0.2, 0.5, *range(1, 16)], dtype=float)
"""Table 5's rows [lifts/min]; above 15 every multiplier is 0."""
_FM = np.array([  # columns: short V<75, short V>=75, moderate V<75, moderate V>=75, long ...
    [1.00, 1.00, .95, .95, .85, .85], [.97, .97, .92, .92, .81, .81],
    [.94, .94, .88, .88, .75, .75], [.91, .91, .84, .84, .65, .65],
    [.88, .88, .79, .79, .55, .55], [.84, .84, .72, .72, .45, .45],
    [.80, .80, .60, .60, .35, .35], [.75, .75, .50, .50, .27, .27],
    [.70, .70, .42, .42, .22, .22], [.60, .60, .35, .35, .18, .18],
    [.52, .52, .30, .30, .00, .15], [.45, .45, .26, .26, .00, .13],
    [.41, .41, .00, .23, .00, .00], [.37, .37, .00, .21, .00, .00],
    [.00, .34, .00, .00, .00, .00], [.00, .31, .00, .00, .00, .00],
    [.00, .28, .00, .00, .00, .00]])
"""Table 5: the frequency multiplier by frequency row and (duration, V below 75 cm or not)."""
_CM = {"good": (1.00, 1.00), "fair": (0.95, 1.00), "poor": (0.90, 0.90)}
"""Table 7: the coupling multiplier for V below 75 cm and at or above it."""
COUPLING_OF_LEVEL = ("good", "fair", "poor", "poor")
"""The Posture CSV's coupling level (REBA's: 0 good, 1 fair, 2 poor, 3 unacceptable) as the
equation's class; it has no class beyond poor."""

COLUMNS = ("niosh_h_cm", "niosh_v_cm", "niosh_d_cm", "niosh_a_deg", "niosh_hm", "niosh_vm",
           "niosh_dm", "niosh_am", "niosh_fm", "niosh_cm", "niosh_rwl_kg", "niosh_li")


class LiftError(ConfigError):
    """A lifting task the equation cannot take; the message is one line."""


@dataclass(frozen=True)
class LiftTask:
    """What the equation needs beyond the hands' location at the handover.

    Defaults: one handover a minute over a shift, set down at 0.75 m (the equation's own
    optimal hand height, a work surface at knuckle height); each is an assumption about the
    workplace, to be replaced by the site's.
    """

    lift_frequency: float = ranged(
        1.0, "lifts per minute (below 0.2 counts as 0.2; Table 5 ends at 15)", 0.0, 15.0,
        "lifts/min")
    lift_duration: str = ranged(
        "long", "work duration: short (up to 1 h), moderate (up to 2 h), long (up to 8 h)",
        choices=DURATIONS)
    lift_destination: float = ranged(
        0.75, "hand height where the box is set down [m] (0-1.75)", 0.0, 1.75, "m")

    def __post_init__(self):
        check_ranges(self, LiftError)


def frequency_multiplier(frequency: np.ndarray, duration: str,
                         low: np.ndarray) -> np.ndarray:
    """Table 5 at each frequency [lifts/min], ``low`` where the origin's V is below 75 cm."""
    f = np.maximum(np.asarray(frequency, dtype=float), FREQUENCIES[0])
    high = ~np.asarray(low, dtype=bool)
    out = np.zeros(np.broadcast(f, high).shape)
    for column, is_high in ((2 * DURATIONS.index(duration), False),
                            (2 * DURATIONS.index(duration) + 1, True)):
        values = _FM[:, column]
        last = FREQUENCIES[np.flatnonzero(values)[-1]]
        fm = np.where(f <= last, np.interp(f, FREQUENCIES, values), 0.0)
        out = np.where(high == is_high, fm, out)
    return out


A_MAX_DEG = 135.0
"""The asymmetry angle beyond which AM is 0 (in either system of units) [deg]."""


class Units(NamedTuple):
    """The equation's constants in one system of units (manual, p. 7): load constant; H's floor
    and the reach beyond which HM is 0; V's optimum, slope and reach; D's floor, numerator and
    reach; the V of Tables 5 and 7's two columns."""

    load_constant: float
    h_min: float
    h_max: float
    v_optimum: float
    v_slope: float
    v_max: float
    d_min: float
    d_numerator: float
    d_max: float
    v_column: float


UNITS = {"metric": Units(23.0, 25.0, 63.0, 75.0, 0.003, 175.0, 25.0, 4.5, 175.0, 75.0),
         "us": Units(51.0, 10.0, 25.0, 30.0, 0.0075, 70.0, 10.0, 1.8, 70.0, 30.0)}
"""Metric (kg, cm), the default, and U.S. customary (lb, in), in which the manual's worked
examples are printed; the two are rounded separately, so they differ by up to a few %."""


def multipliers(h, v, d, a_deg, frequency, duration: str, coupling: np.ndarray,
                units: str = "metric") -> dict[str, np.ndarray]:
    """The six multipliers (``niosh_hm`` ... ``niosh_cm``) of N lifts, H, V, D in the units'
    length (cm or in); ``coupling`` holds class names of :data:`COUPLINGS`. A negative H, V, D
    or A, or a frequency beyond 15, raises :class:`LiftError` naming the row."""
    u = UNITS[units]
    h, v, d, a = (np.asarray(x, dtype=float) for x in (h, v, d, a_deg))
    for name, values in (("H", h), ("V", v), ("D", d), ("A", a)):
        bad = np.flatnonzero(~(values >= 0))
        if bad.size:
            raise LiftError(f"{name} = {values[bad[0]]:g} in row {bad[0] + 1} is not allowed "
                            "(a distance or angle >= 0)")
    f = np.asarray(frequency, dtype=float)
    if np.any(~(f >= 0) | (f > FREQUENCIES[-1])):
        raise LiftError(f"lift_frequency = {np.max(f):g} is beyond Table 5 (0-15 lifts/min)")
    hm = np.where(h <= u.h_max, u.h_min / np.maximum(h, u.h_min), 0.0)
    vm = np.where(v <= u.v_max, 1.0 - u.v_slope * np.abs(v - u.v_optimum), 0.0)
    dm = np.where(d <= u.d_max, 0.82 + u.d_numerator / np.maximum(d, u.d_min), 0.0)
    am = np.where(a <= A_MAX_DEG, 1.0 - 0.0032 * a, 0.0)
    low = v < u.v_column
    fm = frequency_multiplier(f, duration, low)
    coupling = np.asarray(coupling)
    cm = np.zeros(v.shape)
    for name, (below, above) in _CM.items():
        cm = np.where(coupling == name, np.where(low, below, above), cm)
    return {"niosh_hm": hm, "niosh_vm": vm, "niosh_dm": dm, "niosh_am": am, "niosh_fm": fm,
            "niosh_cm": cm}


def recommended_weight_limit(m: dict[str, np.ndarray], units: str = "metric") -> np.ndarray:
    """RWL: the load constant times the six multipliers [kg or lb]."""
    return UNITS[units].load_constant * np.prod(np.stack(list(m.values())), axis=0)


def lift_at(locations: np.ndarray, load_kg: np.ndarray, coupling_level: np.ndarray,
            task: LiftTask) -> dict[str, np.ndarray]:
    """Every column of :data:`COLUMNS` for lifts whose origin is each handover location
    (N, 3) [m, worker frame: x right, y up, z forward], of ``load_kg``, with the Posture CSV's
    ``coupling_level``."""
    p = np.asarray(locations, dtype=float)
    h = 100.0 * np.hypot(p[:, 0], p[:, 2])
    v = 100.0 * p[:, 1]
    d = np.abs(100.0 * task.lift_destination - v)
    a = np.degrees(np.arctan2(np.abs(p[:, 0]), p[:, 2]))
    level = np.clip(np.asarray(coupling_level, dtype=int), 0, 3)
    m = multipliers(h, v, d, a, np.full(len(p), task.lift_frequency), task.lift_duration,
                    np.array(COUPLING_OF_LEVEL)[level])
    rwl = recommended_weight_limit(m)
    load = np.asarray(load_kg, dtype=float)
    li = np.where(rwl > 0, load / np.where(rwl > 0, rwl, 1.0), np.inf)
    return {"niosh_h_cm": h, "niosh_v_cm": v, "niosh_d_cm": d, "niosh_a_deg": a, **m,
            "niosh_rwl_kg": rwl, "niosh_li": li}
