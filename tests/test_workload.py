"""OWAS, the revised NIOSH lifting equation and the static back load: the published worked
examples, the code table, the physics of the lever model, and the refusals."""

from __future__ import annotations

import numpy as np
import pytest

from ergohandover.ergonomics import Posture
from ergohandover.ergonomics.posture import REQUIRED_COLUMNS
from ergohandover.twin.anthropometry import GRAVITY, BodySpec
from ergohandover.workload import Levers, LiftError, LiftTask, back_load, lift_at, owas
from ergohandover.workload.back import ERECTOR_ARM_M
from ergohandover.workload.lifting import multipliers, recommended_weight_limit
from ergohandover.workload.manikins import MANIKINS, manikin
from ergohandover.workload.owas import TABLE

POUND = 0.45359237


def postures(n: int = 1, **columns) -> Posture:
    """Upright postures (every required angle 0) with ``columns`` set."""
    base = {c: np.zeros(n) for c in REQUIRED_COLUMNS}
    return Posture(base | {k: np.broadcast_to(np.asarray(v, float), (n,)).copy()
                           for k, v in columns.items()})


# --- the revised NIOSH lifting equation --------------------------------------------------------

def test_example_2_of_the_applications_manual_loading_supply_rolls():
    """Waters et al. 1994, Example 2 (as transcribed with its worksheet, Figure 9): a 35 lb roll,
    poor coupling, less than one lift in 5 min for under an hour, lifted 17 in from H 15 in,
    V 27 in to H 20 in, V 10 in, no twist. Printed: multipliers .67 .98 .93 1.00 (FM 1.0) .90 at
    the origin and .50 .85 .93 at the destination; RWL 28.0 and 18.1 lb; LI 1.3 and 1.9."""
    m = multipliers(h=[15, 20], v=[27, 10], d=[17, 17], a_deg=[0, 0], frequency=[0.1, 0.1],
                    duration="short", coupling=np.array(["poor", "poor"]), units="us")
    printed = {"niosh_hm": [.67, .50], "niosh_vm": [.98, .85], "niosh_dm": [.93, .93],
               "niosh_am": [1.0, 1.0], "niosh_fm": [1.0, 1.0], "niosh_cm": [.90, .90]}
    for name, values in printed.items():
        assert np.round(m[name], 2).tolist() == values, name
    rounded = 51 * np.prod([np.round(v, 2) for v in m.values()], axis=0)
    assert np.round(rounded, 1).tolist() == [28.0, 18.1]
    rwl = recommended_weight_limit(m, "us")
    assert np.allclose(rwl, [28.0, 18.1], rtol=0.015)  # unrounded multipliers
    assert np.round(35 / rwl, 1).tolist() == [1.3, 1.9]


def test_example_4_of_the_applications_manual_package_inspection_origin():
    """Example 4's origin (its worksheet as transcribed): 26 lb, V 22 in, H within 10 in, no
    twist, D 37 in, fair coupling: HM 1.0, VM .94, DM .87, AM 1.0, CM .95 and, with the printed
    FM .88, RWL 34.9 lb (34.8 unrounded). The task's frequency and duration were not read; both
    readings that give .88 at this height (3 a minute for under an hour, 1 a minute for up to
    two) are checked."""
    for frequency, duration in ((3.0, "short"), (1.0, "moderate")):
        m = multipliers(h=[10], v=[22], d=[37], a_deg=[0], frequency=[frequency],
                        duration=duration, coupling=np.array(["fair"]), units="us")
        shown = {k: round(float(v[0]), 2) for k, v in m.items()}
        assert shown == {"niosh_hm": 1.0, "niosh_vm": .94, "niosh_dm": .87, "niosh_am": 1.0,
                         "niosh_fm": .88, "niosh_cm": .95}
        assert round(51 * np.prod(list(shown.values())), 1) == 34.9
        assert round(float(recommended_weight_limit(m, "us")[0]), 1) == 34.8


def test_metric_and_us_forms_agree_within_their_separate_rounding():
    rng = np.random.default_rng(3)
    h, v, d = rng.uniform(25, 63, 200), rng.uniform(0, 175, 200), rng.uniform(25, 175, 200)
    kwargs = {"a_deg": rng.uniform(0, 135, 200), "frequency": np.full(200, 2.0),
              "duration": "moderate", "coupling": np.full(200, "good")}
    metric = recommended_weight_limit(multipliers(h, v, d, **kwargs))
    us = recommended_weight_limit(multipliers(h / 2.54, v / 2.54, d / 2.54, **kwargs,
                                              units="us"), "us")
    # The metric and U.S. constants are rounded separately (25 cm is not 10 in): a few %.
    assert np.allclose(metric, us * POUND, rtol=0.04)
    assert not np.allclose(metric, us * POUND, rtol=1e-6)


def test_each_multiplier_follows_its_formula_and_limits():
    m = multipliers(h=[10, 25, 50, 64], v=[75, 0, 175, 176], d=[10, 25, 100, 176],
                    a_deg=[0, 90, 135, 136], frequency=[0.0, 0.2, 1.5, 15.0],
                    duration="short", coupling=np.array(["good", "fair", "poor", "fair"]))
    assert m["niosh_hm"].tolist() == pytest.approx([1.0, 1.0, 0.5, 0.0])  # H >= 25; 0 past 63
    assert m["niosh_vm"].tolist() == pytest.approx([1.0, 0.775, 0.7, 0.0])
    assert m["niosh_dm"].tolist() == pytest.approx([1.0, 1.0, 0.865, 0.0])
    assert m["niosh_am"].tolist() == pytest.approx([1.0, 1 - 0.288, 1 - 0.432, 0.0])
    # Table 5, short, V >= 75 cm: below 0.2 counts as 0.2; 1.5 halfway between .94 and .91;
    # 15 a minute is the last row, .28, only for V >= 75 (V < 75 is .00 there).
    assert m["niosh_fm"].tolist() == pytest.approx([1.0, 1.0, 0.925, 0.28])
    assert m["niosh_cm"].tolist() == pytest.approx([1.0, 0.95, 0.90, 1.0])


def test_above_a_columns_last_frequency_the_limit_is_zero():
    m = multipliers(h=[25, 25], v=[50, 100], d=[25, 25], a_deg=[0, 0], frequency=[8.5, 8.5],
                    duration="long", coupling=np.array(["good", "good"]))
    # Long duration, V < 75 ends at 8 a minute (.18); V >= 75 goes on to 10 (.15 at 9).
    assert m["niosh_fm"].tolist() == pytest.approx([0.0, (0.18 + 0.15) / 2])


@pytest.mark.parametrize("field, value", [("h", -1.0), ("v", -0.1), ("d", -5.0)])
def test_negative_distances_are_refused_naming_the_row(field, value):
    args = {"h": [30, 30], "v": [80, 80], "d": [30, 30]}
    args[field] = [30, value]
    with pytest.raises(LiftError, match=rf"^{field.upper()} = {value:g} in row 2 .*>= 0"):
        multipliers(**args, a_deg=[0, 0], frequency=[1, 1], duration="short",
                    coupling=np.array(["good", "good"]))


def test_a_frequency_beyond_the_table_and_a_bad_task_are_refused():
    with pytest.raises(LiftError, match="beyond Table 5"):
        multipliers([30], [80], [30], [0], [16.0], "short", np.array(["good"]))
    with pytest.raises(LiftError, match="lift_frequency = 20"):
        LiftTask(lift_frequency=20)
    with pytest.raises(LiftError, match=r"lift_destination = -0\.5"):
        LiftTask(lift_destination=-0.5)
    with pytest.raises(LiftError, match="lift_duration = 'shift'"):
        LiftTask(lift_duration="shift")


def test_a_handover_location_is_the_lifts_origin():
    task = LiftTask(lift_frequency=0.1, lift_duration="short", lift_destination=1.0)
    out = lift_at(np.array([[0.3, 1.0, 0.4], [0.0, 0.5, 0.2]]), np.array([10.0, 30.0]),
                  np.array([0, 3]), task)
    assert out["niosh_h_cm"] == pytest.approx([50.0, 20.0])  # from between the ankles
    assert out["niosh_v_cm"] == pytest.approx([100.0, 50.0])
    assert out["niosh_d_cm"] == pytest.approx([0.0, 50.0])
    assert out["niosh_a_deg"] == pytest.approx([np.degrees(np.arctan2(0.3, 0.4)), 0.0])
    assert out["niosh_cm"] == pytest.approx([1.0, 0.90])  # an unacceptable grip counts as poor
    rwl = 23 * out["niosh_hm"] * out["niosh_vm"] * out["niosh_dm"] * out["niosh_am"] \
        * out["niosh_fm"] * out["niosh_cm"]
    assert out["niosh_rwl_kg"] == pytest.approx(rwl)
    assert out["niosh_li"] == pytest.approx(np.array([10.0, 30.0]) / rwl)


# --- OWAS --------------------------------------------------------------------------------------

def test_the_owas_table_has_every_cell_and_its_consensus_corners():
    assert TABLE.shape == (4, 3, 7, 3) and set(np.unique(TABLE)) == {1, 2, 3, 4}
    assert TABLE[0, 0, 1, 0] == 1  # 1121: upright, arms down, two straight legs, light: normal
    assert TABLE[1, 0, 2, 1] == 2  # 2132
    assert TABLE[3, 2, 3, 2] == 4  # 4343
    assert TABLE[2, 0, 4, 0] == 4  # twisted on one bent leg
    # Load matters more as the back bends: never less harmful with a heavier load.
    assert np.all(np.diff(TABLE, axis=3) >= 0)


def test_owas_codes_from_angles():
    p = postures(5, trunk_flexion=[0, 30, 5, 30, 0], trunk_twist=[0, 0, 25, 25, 0],
                 left_upper_arm_flexion=[0, 0, 100, 100, 0],
                 right_upper_arm_abduction=[0, 0, 0, 95, 0],
                 left_knee_flexion=[0, 40, 0, 0, 60], right_knee_flexion=[0, 40, 0, 0, 60],
                 bilateral_support=[1, 1, 0, 1, 1], seated=[0, 0, 0, 0, 1],
                 load_kg=[5, 10, 15, 25, 0])
    out = owas(p)
    assert out["owas_code"].tolist() == [1121, 2141, 3232, 4323, 1111]
    expected = [TABLE[b - 1, a - 1, g - 1, w - 1] for b, a, g, w in
                ((1, 1, 2, 1), (2, 1, 4, 1), (3, 2, 3, 2), (4, 3, 2, 3), (1, 1, 1, 1))]
    assert out["owas"].tolist() == expected


# --- the static back load ----------------------------------------------------------------------

def levers() -> Levers:
    return Levers(trunk=(0.5, 30.0, 0.4), head=(0.25, 6.0, 0.5), shoulder_drop=0.05,
                  upper_arm=(0.3, 2.0, 0.5), forearm=(0.25, 1.5, 0.5), hand=(0.2, 0.5, 0.5),
                  grip_offset=0.08, lumbar_strength_nm=250.0)


def test_a_published_lever_example_of_the_erector_force():
    """The simple model's lever arithmetic against a worked example of it (a question-and-
    answer page, anonymous): the spine 35° above horizontal (55° of trunk flexion), 510 N of
    upper body 0.25 m and a 150 N load 0.4 m from L5/S1 along the trunk, a 5 cm erector arm:
    erector force 3,071.82 N. (Its compression and shear resolve the weights along the spine
    with the complementary angle, so they are not a check of this model.)"""
    lv = Levers(trunk=(0.4, 510 / GRAVITY, 0.625), head=(0.4, 150 / GRAVITY, 0.0),
                shoulder_drop=0.0, upper_arm=(0.3, 0.0, 0.5), forearm=(0.3, 0.0, 0.5),
                hand=(0.1, 0.0, 0.5), grip_offset=0.0, lumbar_strength_nm=300.0)
    # The load at C7, 0.4 m up the trunk: the "head" segment's mass at its proximal end.
    out = back_load(postures(1, trunk_flexion=55.0), lv)
    erector = out["back_compression_n"][0] - 660.0 * np.cos(np.radians(55.0))
    assert erector == pytest.approx(3071.82, abs=0.01)
    assert out["back_moment_nm"][0] / ERECTOR_ARM_M == pytest.approx(3071.82, abs=0.01)
    assert out["back_shear_n"][0] == pytest.approx(660.0 * np.sin(np.radians(55.0)))


def test_upright_with_arms_hanging_the_back_carries_only_weight():
    lv = levers()
    out = back_load(postures(1), lv)
    above = 30 + 6 + 2 * (2 + 1.5 + 0.5)
    assert out["back_moment_nm"][0] == pytest.approx(0.0, abs=1e-9)
    assert out["back_compression_n"][0] == pytest.approx(above * GRAVITY)
    assert out["back_shear_n"][0] == pytest.approx(0.0, abs=1e-9)
    # No moment: every strength exceeds it but for 3.6 SDs below the mean (CV 0.277).
    assert out["back_capable_pct"][0] == pytest.approx(99.985, abs=1e-3)


def test_arms_forward_with_a_load_the_moments_follow_the_levers():
    lv = levers()
    load = 10.0
    out = back_load(postures(1, left_upper_arm_flexion=90, right_upper_arm_flexion=90,
                             load_kg=load), lv)
    # Arms straight forward at shoulder height: every arm mass and the load in front of L5/S1.
    reach = {"upper": 0.5 * 0.3, "fore": 0.3 + 0.5 * 0.25, "hand": 0.3 + 0.25 + 0.5 * 0.2,
             "grip": 0.3 + 0.25 + 0.08}
    per_arm = 2.0 * reach["upper"] + 1.5 * reach["fore"] + 0.5 * reach["hand"] \
        + load / 2 * reach["grip"]
    assert out["back_moment_nm"][0] == pytest.approx(2 * per_arm * GRAVITY)
    assert out["shoulder_moment_nm"][0] == pytest.approx(per_arm * GRAVITY)
    elbow = 1.5 * 0.125 + 0.5 * (0.25 + 0.1) + load / 2 * (0.25 + 0.08)
    assert out["elbow_moment_nm"][0] == pytest.approx(elbow * GRAVITY)
    share = out["back_moment_nm"][0] / 250.0
    assert out["back_strength_share"][0] == pytest.approx(share)
    assert 0 < out["back_capable_pct"][0] < 100


def test_bending_further_loads_the_back_more_and_mirrors_are_equal():
    lv = levers()
    flex = np.array([0, 20, 40, 60, 80.0])
    out = back_load(postures(5, trunk_flexion=flex, load_kg=8.0), lv)
    assert np.all(np.diff(out["back_moment_nm"]) > 0)
    assert np.all(np.diff(out["back_compression_n"]) > 0)
    assert np.all(np.diff(out["back_capable_pct"]) < 0)
    arms = postures(2, left_upper_arm_flexion=[60, 20], right_upper_arm_flexion=[20, 60],
                    left_elbow_flexion=[30, 70], right_elbow_flexion=[70, 30])
    mirrored = back_load(arms, lv)
    for column in ("back_moment_nm", "back_compression_n", "shoulder_moment_nm"):
        assert mirrored[column][0] == pytest.approx(mirrored[column][1])


def test_the_lumbar_moment_is_the_twins_own_in_the_sagittal_plane():
    """The model reads only the Posture columns; the twin's kinematics hold every segment's
    mass where the solved posture put it. For the twin's own postures in its mid-sagittal plane
    — upright to bent 68°, the box low to high, near to far — the two moments about L5/S1 (the
    lumbar joint) agree to 4 %."""
    from ergohandover.ergonomics.posture import POSTURE_COLUMNS
    from ergohandover.twin.evaluate import Evaluator, evaluate, joint_angles, posture_solver

    evaluator = Evaluator()
    points = np.array([[0.0, y, z] for y in (0.5, 0.7, 0.9, 1.1, 1.3) for z in (0.3, 0.45, 0.6)])
    table = evaluate(points, evaluator, joints=True)
    table = table[table["feasible"].astype(bool)]
    assert len(table) >= 10 and table["trunk_flexion"].max() > 60
    solver = posture_solver(evaluator)
    state = solver.model.forward(joint_angles(table))
    lumbar = solver.model.index("lumbar_flexion")
    lever = state.subtree_levers(solver.grip_loads())[lumbar]
    twin = GRAVITY * np.abs(np.cross(state.joint_axes[lumbar], lever, axis=0)[2])
    posture = Posture({c: table[c].to_numpy(float) for c in POSTURE_COLUMNS})
    model = back_load(posture, Levers.of(evaluator.body))["back_moment_nm"]
    np.testing.assert_allclose(model, twin, rtol=0.04)


def test_the_levers_are_the_body_models():
    body = BodySpec()
    lv = Levers.of(body)
    masses = body.segment_masses()
    assert lv.trunk[1] == masses["trunk"].mass_kg and lv.hand[1] == masses["hand"].mass_kg
    assert lv.upper_arm[0] == body.segments().upper_arm_length
    assert lv.lumbar_strength_nm == body.joint_strengths_nm()["lumbar_flexion"]


# --- the manikins ------------------------------------------------------------------------------

def test_the_four_manikins_are_ordered_by_size_and_sexed():
    bodies = {name: manikin(name) for name in MANIKINS}
    assert [b.sex for b in bodies.values()] == ["female", "female", "male", "male"]
    statures = [b.stature_m for b in bodies.values()]
    masses = [b.mass_kg for b in bodies.values()]
    assert statures == sorted(statures) and masses == sorted(masses)
    assert bodies["m50"] == BodySpec()  # the study's default worker is the 50th man


def test_an_infinite_lifting_index_and_a_failing_shift_say_why():
    from ergohandover.workload.flags import flags

    said = flags({"niosh_h_cm": 70.2, "niosh_v_cm": 100.0, "niosh_d_cm": 30.0,
                  "niosh_a_deg": 140.0, "niosh_li": float("inf"),
                  "shift_failure_min": 2.4})
    assert ("lifting index inf over 1: the recommended weight limit is 0 because H 70.2 cm is "
            "beyond its 63 cm reach and A 140.0° is beyond its 135° reach") in said
    assert "over the shift a joint fails its hold after 2 min" in said
    quiet = flags({"niosh_h_cm": 40.0, "niosh_li": 0.8, "shift_failure_min": float("inf")})
    assert quiet == []


def test_a_joint_that_never_fails_reads_never_on_the_page():
    from ergohandover.viewer.report_page import shown

    assert shown("shift_failure_min", float("inf")) == "never"
    assert shown("niosh_li", float("inf")) == "inf"
    assert shown("shift_failure_min", 12.345) == "12.3"
