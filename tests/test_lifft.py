"""LiFFT's daily dose of lifting: the calculator's worked examples, and the load's lever from a
posture."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import neutral_columns

from ergohandover.ergonomics import Posture
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.workload.back import Levers, grip_reach_m
from ergohandover.workload.lifft import (
    NM_PER_FT_LB,
    daily_dose,
    damage_per_lift,
    high_risk_probability,
    peak_load_moment_nm,
)

POUND_KG, INCH_M = 0.45359237, 0.0254


def test_the_calculators_worked_examples():
    # LiFFT's instructions: 30 lb at 16 in, 760 lifts a day: PLM 40 ft·lb, risk about 40 %.
    plm = peak_load_moment_nm(30 * POUND_KG, 16 * INCH_M)
    assert plm / NM_PER_FT_LB == pytest.approx(40.0, rel=1e-3)
    dose = daily_dose(plm, 760)
    assert dose == pytest.approx(0.0090, abs=5e-5)
    assert high_risk_probability(dose) == pytest.approx(0.408, abs=0.002)
    # The authors' manuscript: 13 kg held 40 cm away, 400 lifts: PLM 51 N m, damage about
    # 0.000011 a lift, a daily dose of 0.0042 (the v1.4.0 calculator's risk: about 33 %).
    plm = peak_load_moment_nm(13, 0.40)
    assert plm == pytest.approx(51.0, abs=0.1)
    assert damage_per_lift(plm) == pytest.approx(1.1e-5, abs=0.05e-5)
    assert daily_dose(plm, 400) == pytest.approx(0.0042, abs=5e-5)
    assert high_risk_probability(daily_dose(plm, 400)) == pytest.approx(0.33, abs=0.005)


def test_the_dose_grows_with_the_lever_and_the_lifts_and_the_risk_with_the_dose():
    plm = peak_load_moment_nm(6.0, np.array([0.2, 0.3, 0.4]))
    assert (np.diff(damage_per_lift(plm)) > 0).all()
    assert daily_dose(plm[0], 800) == pytest.approx(2 * daily_dose(plm[0], 400))
    doses = np.array([1e-4, 1e-3, 1e-2, 1e-1])
    risk = high_risk_probability(doses)
    assert (np.diff(risk) > 0).all() and ((risk > 0) & (risk < 1)).all()


def test_the_load_is_held_further_forward_the_more_the_trunk_leans_and_the_arms_reach():
    levers = Levers.of(BodySpec())
    upright = Posture(neutral_columns())
    # The arms hang straight down from a trunk bent 40° (their flexion is the trunk's).
    leaning = Posture(neutral_columns(trunk_flexion=40.0, left_upper_arm_flexion=40.0,
                                      right_upper_arm_flexion=40.0))
    reaching = Posture(neutral_columns(left_upper_arm_flexion=60.0,
                                       right_upper_arm_flexion=60.0))
    base = float(grip_reach_m(upright, levers)[0])
    assert float(grip_reach_m(leaning, levers)[0]) > base + 0.2
    assert float(grip_reach_m(reaching, levers)[0]) > base + 0.15  # the forearm rises
