"""Each joint's load as a share of its strength, and a shift of handovers at a posture."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import neutral_columns

from ergohandover.ergonomics import Posture
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.workload.fatigue import Shift
from ergohandover.workload.lifft import daily_dose, damage_per_lift
from ergohandover.workload.strength import load_shares, shift_columns, strengths_nm


def test_strengths_are_harbos_regressions_and_the_twins_back():
    man, woman = BodySpec.from_percentile("p50-male"), BodySpec.from_percentile("p50-female")
    found = strengths_nm(man)
    # Harbo et al. 2012 at 40 years: elbow flexion -23.8 - 0.13 A + 22 H + 0.51 W (men).
    assert found["elbow"] == pytest.approx(-23.8 - 0.13 * 40 + 22 * man.stature_m
                                           + 0.51 * man.mass_kg)
    assert found["shoulder"] == pytest.approx(-30.8 - 0.24 * 40 + 36 * man.stature_m
                                              + 0.49 * man.mass_kg)
    assert found["trunk"] == man.joint_strengths_nm()["lumbar_flexion"]
    assert all(strengths_nm(woman)[j] < found[j] for j in found)
    assert strengths_nm(man, age=70)["elbow"] < found["elbow"]


def test_a_heavier_box_held_further_loads_every_joint_more():
    body = BodySpec()
    light = Posture(neutral_columns(load_kg=2.0, left_upper_arm_flexion=45.0,
                                    right_upper_arm_flexion=45.0))
    heavy = Posture(neutral_columns(load_kg=10.0, left_upper_arm_flexion=45.0,
                                    right_upper_arm_flexion=45.0))
    far = Posture(neutral_columns(load_kg=10.0, left_upper_arm_flexion=80.0,
                                  right_upper_arm_flexion=80.0, left_elbow_flexion=10.0,
                                  right_elbow_flexion=10.0))
    a, b, c = (load_shares(p, body) for p in (light, heavy, far))
    for joint in ("shoulder", "elbow", "trunk"):
        assert b[joint][0] > a[joint][0]
    assert c["shoulder"][0] > b["shoulder"][0] and c["trunk"][0] > b["trunk"][0]


def test_a_shifts_columns_are_its_joints_worst_and_lifts_dose():
    from ergohandover.workload.back import Levers, grip_reach_m
    from ergohandover.workload.lifft import peak_load_moment_nm

    columns = {k: np.repeat(v, 3) for k, v in neutral_columns(load_kg=8.0).items()}
    columns.update(left_upper_arm_flexion=np.array([0.0, 60.0, 90.0]),
                   right_upper_arm_flexion=np.array([0.0, 60.0, 90.0]),
                   trunk_flexion=np.array([0.0, 30.0, 60.0]))
    posture, body = Posture(columns), BodySpec()
    plan = Shift(rate_per_min=6.0, hold_s=8.0, hours=8.0)
    out = shift_columns(posture, body, plan)
    joints = ("shoulder", "elbow", "trunk")
    first = np.min([out[f"{j}_failure_min"] for j in joints], axis=0)
    assert np.array_equal(out["shift_failure_min"], first)
    alive = np.isinf(first)
    assert alive.any() and not alive.all()  # the far, bent posture fails within the shift
    lowest = np.min([out[f"{j}_capacity_end"] for j in joints], axis=0)
    assert np.allclose(out["shift_capacity_end"][alive], lowest[alive])
    assert np.isnan(out["shift_capacity_end"][~alive]).all()
    plm = peak_load_moment_nm(8.0, grip_reach_m(posture, Levers.of(body)))
    assert np.allclose(out["lifft_dose"], daily_dose(plm, plan.handovers))
    assert np.allclose(out["lifft_dose"], plan.handovers * damage_per_lift(plm))
    assert (np.diff(out["lifft_dose"]) > 0).all()  # the further the reach, the larger the dose


def test_a_workers_shift_is_kept_only_where_every_joint_keeps_enough_and_none_fails():
    from ergohandover.workload.fatigue import never_failing_load, shift
    from ergohandover.workload.strength import shift_outcome

    plan = Shift(6.0, 8.0, 8.0)
    light, heavy = 0.05, 0.6  # a light load keeps most; a heavy one fails within the shift
    assert np.isfinite(shift(heavy, "elbow", plan).failure_min)
    assert heavy > never_failing_load("elbow")
    shares = {"shoulder": np.array([light, light, light, np.nan]),
              "elbow": np.array([light, heavy, light, np.nan]),
              "trunk": np.array([light, light, 0.3, np.nan])}
    kept_at_end = float(shift(0.3, "trunk", plan).capacity_end)
    found = shift_outcome(shares, plan, keep=(1 + kept_at_end) / 2)  # the trunk's 0.3 falls short
    assert found["kept"].tolist() == [True, False, False, False]
    assert found["fails"].tolist() == [False, True, False, False]  # NaN: the box not taken
    assert shift_outcome(shares, plan, keep=kept_at_end - 1e-9)["kept"].tolist() == [
        True, False, True, False]
