"""Joint fatigue over a shift of repeated handovers: the three-compartment model with rest
recovery, and the endurance-time power laws it is checked against.

**The model** (Xia & Frey-Law 2008, J Biomech 41:3046; joint-specific rates of Frey-Law, Looft &
Heitsman 2012, J Biomech 45:1803; recovery during rest of Looft, Herkert & Frey-Law 2018,
J Biomech 77:16). A joint's motor units are active (MA), fatigued (MF) or resting (MR), as
shares of the joint's strength that sum to 1. A task asks a target load TL, the joint's moment
as a share of its strength; a controller recruits resting units toward it, active units fatigue
at rate F and fatigued units recover at rate R (r·R while the joint rests, TL = 0):

    dMA/dt = C − F·MA,    dMF/dt = F·MA − R'·MF,    MR = 1 − MA − MF,
    C = L_D·(TL − MA) while MA < TL and enough units rest (MR > TL − MA), else L_D·MR;
    C = L_R·(TL − MA) once MA ≥ TL (at rest, TL = 0: every active unit returns).

The joint **fails** the task when what it can still give, MA + MR = 1 − MF (its **capacity**),
falls below TL. Under a sustained load the failure time has a closed form
(:func:`endurance_time`), and a load at or below R/(F + R) never fails
(:func:`never_failing_load`).

**A shift** (:func:`shift`): handovers at a steady rate, each a hold of TL for ``hold`` seconds,
then rest until the next. Within a hold (before failure) and within a rest the model is linear,
so each phase is integrated exactly (:func:`_hold`, :func:`_rest`), and the time of a failure
inside a hold is found by bisection on the exact solution. Starting rested, the state before a
failure is also proportional to TL, so the shift is followed once at a load of 1 and every
load reads it: a shift of thousands of handovers at a million locations costs a few numpy
operations per location.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..errors import ConfigError

GAIN_PER_S = 10.0
"""The controller's gains L_D = L_R [1/s]: "an arbitrary constant tracking factor" of the
model's authors (Xia & Frey-Law 2008; the value used by Frey-Law et al. 2012 and Looft et al.
2018). The steady active share under a load is L·TL/(L + F), within 0.2 % of TL."""
REST_RECOVERY = 15.0
"""r, how much faster fatigued units recover while the joint rests (TL = 0): the value that
fitted the ankle, knee and elbow best (Looft, Herkert & Frey-Law 2018, J Biomech 77:16; grip's
best was 30, the shoulder was not studied); used for every joint here."""


@dataclass(frozen=True)
class JointRates:
    """A joint's fatigue and recovery rates [1/s] (Frey-Law, Looft & Heitsman 2012, Table 1)
    and its endurance power law, ET = b0·TL^b1 [s] for TL a share of strength (Frey-Law &
    Avin 2010, Ergonomics 53:109, Table 2; fitted on 10–100 % of strength)."""

    fatigue: float
    recovery: float
    b0: float
    b1: float


JOINTS: dict[str, JointRates] = {
    "shoulder": JointRates(0.01820, 0.00168, 14.86, -1.83),
    "elbow": JointRates(0.00912, 0.00094, 17.98, -2.21),
    "trunk": JointRates(0.00755, 0.00075, 22.69, -2.27),
    "knee": JointRates(0.01500, 0.00149, 19.38, -1.88),
    "ankle": JointRates(0.00589, 0.00058, 34.71, -2.06),
    "hand": JointRates(0.00980, 0.00064, 33.55, -1.61),
    "general": JointRates(0.00970, 0.00091, 21.92, -1.98),
}
"""Each joint's rates and power law. F and R as published in Frey-Law et al. 2012, Table 1, and
b0, b1 in Frey-Law & Avin 2010, Table 2, both read as stated by MyoSuite's fatigue validation
(MyoHub/myosuite, tests/test_fatigue_validation.py and docs/source/fatigue_validation.rst,
Apache-2.0). The power laws' 95 % prediction band lies 29–47 % either side of the curve
(:data:`POWER_LAW_BAND`)."""
POWER_LAW_BAND = 0.47
"""The widest half-width of the power laws' 95 % prediction band, as a share of the curve
(29–47 % by joint: Frey-Law et al. 2012's account of Frey-Law & Avin 2010)."""


def rates(joint: str) -> JointRates:
    """The joint's rates; a one-line ConfigError naming the joints otherwise."""
    if joint not in JOINTS:
        raise ConfigError(f"joint = {joint!r} is not allowed (use {', '.join(JOINTS)})")
    return JOINTS[joint]


def never_failing_load(joint: str) -> float:
    """The largest sustained load (share of strength) the joint never fails: R/(F + R)."""
    r = rates(joint)
    return r.recovery / (r.fatigue + r.recovery)


def endurance_time(load, joint: str) -> np.ndarray:
    """The closed-form time [s] a sustained ``load`` (share of strength, any shape) is held
    before the joint fails, ``inf`` at or below :func:`never_failing_load` (Frey-Law et al.
    2012: ET = −ln(1 − R(1 − TL)/(F·TL))/R, the controller taken as instantaneous)."""
    r = rates(joint)
    tl = np.asarray(load, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        inside = 1.0 - r.recovery * (1.0 - tl) / (r.fatigue * tl)
        out = -np.log(inside) / r.recovery
    return np.where(tl > never_failing_load(joint), out, np.inf)


def power_law_endurance(load, joint: str) -> np.ndarray:
    """The power law's endurance time [s] at a sustained ``load`` (share of strength)."""
    r = rates(joint)
    return r.b0 * np.asarray(load, dtype=float) ** r.b1


@dataclass(frozen=True)
class Shift:
    """Handovers repeated over a shift.

    Attributes:
        rate_per_min: handovers per minute. Default 1: the lightest rate the study covers (a
            station handing over one part a minute; study/shift/config.py).
        hold_s: how long each handover loads the joints [s]. Default 3: a brisk hand-off, the
            robot letting go as the worker grips (the study also holds 8 s).
        hours: the shift's length [h]. Default 8: a working day.
    """

    rate_per_min: float = 1.0
    hold_s: float = 3.0
    hours: float = 8.0

    def __post_init__(self):
        for name, value in (("rate", self.rate_per_min), ("hold", self.hold_s),
                            ("shift hours", self.hours)):
            if isinstance(value, bool) or not isinstance(value, int | float) or not (
                    math.isfinite(value) and value > 0):
                raise ConfigError(f"{name} = {value!r} is not allowed (a number above 0)")
        if self.hold_s >= self.cycle_s:
            raise ConfigError(f"hold = {self.hold_s:g} s is not allowed at rate "
                              f"{self.rate_per_min:g} a minute: a handover every "
                              f"{self.cycle_s:g} s leaves no rest (hold below the cycle; "
                              f"at most {60.0 / self.hold_s:g} a minute for this hold)")

    @property
    def cycle_s(self) -> float:
        """Seconds from one handover to the next."""
        return 60.0 / self.rate_per_min

    @property
    def handovers(self) -> int:
        """Handovers in the shift (whole cycles)."""
        return int(self.hours * 3600.0 // self.cycle_s)


@dataclass(frozen=True)
class ShiftOutcome:
    """Per load (the shape of the loads given).

    Attributes:
        failure_min: minutes into the shift at which the joint first fails (``inf``: never).
        capacity_end: what the joint can still give at the shift's end, 1 − MF (NaN where it
            failed: the model does not follow a joint past its failure).
        capacity_min: the least it could give before each handover over the shift (NaN where
            it failed).
    """

    failure_min: np.ndarray
    capacity_end: np.ndarray
    capacity_min: np.ndarray


def _hold(ma, mf, tl, t, f, r):
    """(MA, MF) after ``t`` seconds of holding ``tl`` from (``ma``, ``mf``), in the regime
    before failure (C = L·(TL − MA)): exact."""
    a = GAIN_PER_S + f
    ma_inf = GAIN_PER_S * tl / a
    mf_inf = f * ma_inf / r
    k = f * (ma - ma_inf) / (r - a)
    ea, er = np.exp(-a * t), np.exp(-r * t)
    return ma_inf + (ma - ma_inf) * ea, mf_inf + (mf - mf_inf - k) * er + k * ea


def _rest(ma, mf, t, f, r):
    """(MA, MF) after ``t`` seconds of rest (TL = 0, recovery r·R) from (``ma``, ``mf``):
    exact."""
    a, b = GAIN_PER_S + f, REST_RECOVERY * r
    k = f * ma / (b - a)
    ea, eb = np.exp(-a * t), np.exp(-b * t)
    return ma * ea, (mf - k) * eb + k * ea


def _failure_within(ma, mf, tl, hold, f, r, steps: int = 40) -> np.ndarray:
    """The time into a hold at which 1 − MF first falls below TL (bisection on the exact
    solution: MF rises through a hold)."""
    lo, hi = np.zeros_like(tl), np.full_like(tl, hold)
    for _ in range(steps):
        mid = (lo + hi) / 2
        failed = _hold(ma, mf, tl, mid, f, r)[1] > 1.0 - tl
        hi, lo = np.where(failed, mid, hi), np.where(failed, lo, mid)
    return hi


@lru_cache(maxsize=64)
def _per_unit_load(joint: str, plan: Shift) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The shift at a load of 1, followed without failing: MA and MF before each handover and
    at the end ((N + 1,) each) and MF at each hold's end ((N,)). Before a failure the model is
    linear in the load (the recruitment's target is proportional to it, and the shift starts
    at rest), so a load TL's shift is TL times this one until it fails."""
    r = rates(joint)
    basis_ma, basis_mf = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])
    held = _hold(basis_ma, basis_mf, 1.0, plan.hold_s, r.fatigue, r.recovery)
    rested = _rest(basis_ma, basis_mf, plan.cycle_s - plan.hold_s, r.fatigue, r.recovery)
    # Each phase as an affine map of (MA, MF), read off the basis states: a hold's constant
    # part and matrix, a rest's matrix (a rest has no constant part).
    h0 = (float(held[0][0]), float(held[1][0]))
    hm = [[float(held[i][j + 1] - held[i][0]) for j in range(2)] for i in range(2)]
    qm = [[float(rested[i][j + 1]) for j in range(2)] for i in range(2)]
    count = plan.handovers
    ma, mf, peak = np.zeros(count + 1), np.zeros(count + 1), np.zeros(count)
    a, f = 0.0, 0.0
    for n in range(count):  # scalar arithmetic: a shift of thousands costs milliseconds
        ha = h0[0] + hm[0][0] * a + hm[0][1] * f
        hf = h0[1] + hm[1][0] * a + hm[1][1] * f
        peak[n] = hf
        a, f = qm[0][0] * ha + qm[0][1] * hf, qm[1][0] * ha + qm[1][1] * hf
        ma[n + 1], mf[n + 1] = a, f
    return ma, mf, peak


def _first_failing(tl: np.ndarray, joint: str, plan: Shift) -> np.ndarray:
    """The handover in whose hold each load ``tl`` (share of strength, >= 0) first fails
    (``plan.handovers``: none): the first whose hold's end would leave less than the load."""
    _, _, peak = _per_unit_load(joint, plan)
    with np.errstate(divide="ignore"):
        allowed = np.where(tl > 0, (1.0 - tl) / np.where(tl > 0, tl, 1.0), np.inf)
    return np.searchsorted(np.maximum.accumulate(peak), allowed, side="right")


def capacity_at_end(load, joint: str, plan: Shift = Shift()) -> np.ndarray:
    """What the joint can still give at the end of the shift at ``load`` (any shape), 1 − MF;
    NaN where it fails during the shift. As :func:`shift` without timing the failures: the
    cheap question a workforce asks of every worker at every location."""
    tl = np.clip(np.asarray(load, dtype=float), 0.0, None)
    _, mf, _ = _per_unit_load(joint, plan)
    fails = _first_failing(tl.ravel(), joint, plan).reshape(tl.shape) < plan.handovers
    return np.where(fails, np.nan, 1.0 - tl * mf[-1])


def shift(load, joint: str, plan: Shift = Shift()) -> ShiftOutcome:
    """The joint over a shift of handovers at ``load`` (share of strength, any shape; 0: the
    handover does not load it), starting rested.

    The shift at a load of 1 is followed once per joint and shift (:func:`_per_unit_load`);
    a load TL fails at the first hold whose end would leave less than TL, TL·MF > 1 − TL, and
    within it at the time found by bisection on the exact solution; until then its state is TL
    times the unit load's. The cost is the unit shift once, then a few operations per load."""
    r = rates(joint)
    tl = np.clip(np.asarray(load, dtype=float), 0.0, None)
    shape = tl.shape
    tl = tl.ravel()
    ma, mf, _ = _per_unit_load(joint, plan)
    first = _first_failing(tl, joint, plan)
    fails = first < plan.handovers
    failed_at = np.full_like(tl, np.inf)
    if fails.any():
        n, held = first[fails], tl[fails]
        within = _failure_within(held * ma[n], held * mf[n], held, plan.hold_s, r.fatigue,
                                 r.recovery)
        failed_at[fails] = n * plan.cycle_s + within
    alive = ~fails
    return ShiftOutcome((failed_at / 60.0).reshape(shape),
                        np.where(alive, 1.0 - tl * mf[-1], np.nan).reshape(shape),
                        np.where(alive, 1.0 - tl * mf.max(), np.nan).reshape(shape))


def capacity_over_shift(load: float, joint: str, plan: Shift = Shift()) -> np.ndarray:
    """(N + 1,) what the joint can give, 1 − MF, before each of the shift's N handovers at
    ``load`` (share of strength) and at its end; NaN from the handover in which it fails."""
    _, mf, _ = _per_unit_load(joint, plan)
    tl = max(float(load), 0.0)
    capacity = 1.0 - tl * mf
    failed = float(shift(tl, joint, plan).failure_min)
    if math.isfinite(failed):
        capacity[int(failed * 60.0 // plan.cycle_s) + 1:] = np.nan
    return capacity
