"""The three-compartment fatigue model: its closed form, its exact phases against a plain
integration of the equations, the published endurance times, rest and never-failing loads."""

from __future__ import annotations

import numpy as np
import pytest

from ergohandover.errors import ConfigError
from ergohandover.workload import fatigue
from ergohandover.workload.fatigue import (
    GAIN_PER_S,
    JOINTS,
    POWER_LAW_BAND,
    REST_RECOVERY,
    Shift,
    endurance_time,
    never_failing_load,
    power_law_endurance,
    shift,
)


def integrated(load: float, joint: str, hold: float, cycle: float, seconds: float,
               dt: float = 1e-3) -> tuple[float, float]:
    """The model's equations integrated step by step (Euler, every controller branch), handovers
    of ``load`` held ``hold`` s every ``cycle`` s: (the first failure [s] or inf, 1 − MF at
    the end)."""
    r = JOINTS[joint]
    ma, mf = 0.0, 0.0
    for step in range(round(seconds / dt)):
        t = step * dt
        tl = load if (t % cycle) < hold else 0.0
        mr = 1.0 - ma - mf
        if ma < tl:
            c = GAIN_PER_S * (tl - ma) if mr > tl - ma else GAIN_PER_S * mr
        else:
            c = GAIN_PER_S * (tl - ma)
        recovery = r.recovery * (REST_RECOVERY if tl == 0 else 1.0)
        if tl > 0 and 1.0 - mf < tl:
            return t, np.nan
        ma, mf = ma + dt * (c - r.fatigue * ma), mf + dt * (r.fatigue * ma - recovery * mf)
    return np.inf, 1.0 - mf


@pytest.mark.parametrize("joint", list(JOINTS))
def test_the_closed_form_is_the_sustained_load_integrated(joint):
    loads = np.array([0.3, 0.6])
    closed = endurance_time(loads, joint)
    for load, expected in zip(loads, closed, strict=True):
        # A hold longer than the endurance time: the failure falls inside the first hold.
        found = fatigue._failure_within(np.zeros(1), np.zeros(1), np.array([load]),
                                        10 * expected, JOINTS[joint].fatigue,
                                        JOINTS[joint].recovery)[0]
        assert found == pytest.approx(expected, rel=0.02)  # the controller's transient


def test_the_published_endurance_times():
    # The model's closed form with Frey-Law et al. 2012's rates, and Frey-Law & Avin 2010's
    # power laws, as MyoSuite's validation states them [s].
    shoulder = endurance_time([0.1, 0.2, 0.5, 0.8, 0.9], "shoulder")
    assert shoulder == pytest.approx([1059, 274, 57.7, 13.9, 6.2], rel=0.011)
    assert endurance_time([0.2, 0.5], "general") == pytest.approx([517, 108], rel=0.005)
    at_half = {j: float(power_law_endurance(0.5, j)) for j in JOINTS}
    assert at_half == pytest.approx({"shoulder": 52.8, "elbow": 83.2, "hand": 102,
                                     "knee": 71.3, "trunk": 109, "ankle": 145,
                                     "general": 86.5}, rel=0.005)


@pytest.mark.parametrize("joint", list(JOINTS))
def test_the_model_lies_within_the_power_laws_published_band(joint):
    loads = np.linspace(0.1, 0.8, 15)
    ratio = endurance_time(loads, joint) / power_law_endurance(loads, joint)
    assert (np.abs(ratio - 1) <= POWER_LAW_BAND).all(), ratio


def test_the_exact_phases_are_the_equations_integrated_over_handovers():
    plan = Shift(rate_per_min=6.0, hold_s=4.0, hours=0.25)  # 90 handovers of 4 s every 10 s
    loads = np.array([0.05, 0.45, 0.9])
    found = shift(loads, "shoulder", plan)
    for i, load in enumerate(loads):
        failed, capacity = integrated(load, "shoulder", 4.0, 10.0, plan.hours * 3600)
        if np.isinf(failed):
            assert np.isinf(found.failure_min[i])
            assert found.capacity_end[i] == pytest.approx(capacity, abs=2e-3)
        else:
            assert found.failure_min[i] * 60 == pytest.approx(failed, abs=0.05)
            assert np.isnan(found.capacity_end[i])
    assert np.isinf(found.failure_min[0]) and np.isfinite(found.failure_min[2])


def test_a_load_below_the_never_failing_level_never_fails_and_rest_restores_capacity():
    level = never_failing_load("shoulder")
    assert level == pytest.approx(0.00168 / (0.01820 + 0.00168))
    # Sustained in all but a second a minute, all day long: never fails.
    hard = Shift(rate_per_min=1.0, hold_s=59.0, hours=12.0)
    below = shift(np.array([0.99 * level]), "shoulder", hard)
    assert np.isinf(below.failure_min).all() and below.capacity_end[0] > 0.99 * level
    above = shift(np.array([1.5 * level]), "shoulder", hard)  # one second of rest a minute
    assert np.isfinite(above.failure_min).all()
    # Fatigued by a long hold, then rested long enough: back to full capacity.
    r = JOINTS["elbow"]
    ma, mf = fatigue._hold(0.0, 0.0, 0.4, 60.0, r.fatigue, r.recovery)
    assert 1 - mf < 0.9
    _, rested = fatigue._rest(ma, mf, 3600.0, r.fatigue, r.recovery)
    assert 1 - rested == pytest.approx(1.0, abs=1e-3)


def test_more_handovers_or_longer_holds_never_leave_more_capacity():
    loads = np.linspace(0.0, 0.3, 31)
    base = shift(loads, "trunk", Shift(1.0, 3.0, 8.0))
    faster = shift(loads, "trunk", Shift(2.0, 3.0, 8.0))
    longer = shift(loads, "trunk", Shift(1.0, 6.0, 8.0))
    for other in (faster, longer):
        ok = np.isfinite(other.capacity_end)
        assert (other.capacity_end[ok] <= base.capacity_end[ok] + 1e-12).all()
        assert (other.failure_min <= base.failure_min).all()
    assert base.capacity_end[0] == 1.0  # a handover that does not load the joint


@pytest.mark.parametrize(("kwargs", "expected"), [
    ({"rate_per_min": -1.0}, "rate = -1.0 is not allowed"),
    ({"hold_s": 0.0}, "hold = 0.0 is not allowed"),
    ({"hours": float("nan")}, "shift hours = nan is not allowed"),
    ({"rate_per_min": 20.0, "hold_s": 3.0}, "a handover every 3 s leaves no rest"),
])
def test_an_impossible_shift_is_refused_in_one_line(kwargs, expected):
    with pytest.raises(ConfigError, match=expected) as raised:
        Shift(**kwargs)
    assert "\n" not in str(raised.value)
    with pytest.raises(ConfigError, match="'wrist' is not allowed"):
        endurance_time(0.5, "wrist")



def stepped(load: np.ndarray, joint: str, plan: Shift) -> tuple[np.ndarray, np.ndarray]:
    """The shift stepped handover by handover through the exact phases, every load followed
    on its own: (the first failure [min] or inf, 1 - MF at the end or NaN)."""
    r = JOINTS[joint]
    ma, mf = np.zeros_like(load), np.zeros_like(load)
    failed = np.full_like(load, np.inf)
    for n in range(plan.handovers):
        held_ma, held_mf = fatigue._hold(ma, mf, load, plan.hold_s, r.fatigue, r.recovery)
        now = np.isinf(failed) & (held_mf > 1.0 - load) & (load > 0)
        if now.any():
            failed[now] = (n * plan.cycle_s + fatigue._failure_within(
                ma[now], mf[now], load[now], plan.hold_s, r.fatigue, r.recovery)) / 60.0
        ma, mf = fatigue._rest(held_ma, held_mf, plan.cycle_s - plan.hold_s, r.fatigue,
                               r.recovery)
    return failed, np.where(np.isinf(failed), 1.0 - mf, np.nan)


@pytest.mark.parametrize("plan", [Shift(1.0, 3.0, 2.0), Shift(6.0, 8.0, 2.0)])
def test_every_load_reads_the_unit_loads_shift_as_if_followed_on_its_own(plan):
    rng = np.random.default_rng(7)
    loads = np.concatenate([rng.uniform(0.0, 1.2, 2000), [0.0, 1.0, 1.5]])
    failed, end = stepped(loads, "shoulder", plan)
    found = shift(loads, "shoulder", plan)
    assert 0 < np.isinf(failed).sum() < len(loads)  # both sides of the never-failing load
    np.testing.assert_array_equal(np.isinf(found.failure_min), np.isinf(failed))
    fails = np.isfinite(failed)
    np.testing.assert_allclose(found.failure_min[fails], failed[fails], rtol=0, atol=1e-9)
    np.testing.assert_allclose(found.capacity_end, end, rtol=0, atol=1e-12)
    # Without timing the failures: the same capacities, NaN where the joint fails.
    np.testing.assert_array_equal(fatigue.capacity_at_end(loads, "shoulder", plan),
                                  found.capacity_end)
