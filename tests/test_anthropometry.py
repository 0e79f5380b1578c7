"""Behaviour of the worker's anthropometry: sizes, masses, limits and validation."""

from __future__ import annotations

import dataclasses
import math
import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ergohandover.twin.anthropometry import (
    PAIRED_SEGMENTS,
    PERCENTILES,
    BodySpec,
    BodySpecError,
    Segments,
)

VERTICAL_CHAIN = (
    "ankle_height",
    "shank_length",
    "thigh_length",
    "pelvis_height",
    "trunk_length",
    "neck_length",
    "head_height",
)
PROPERTIES = ("knee_height", "hip_height", "shoulder_height", "neck_joint_height")
MASS_SEGMENTS = {
    "foot",
    "shank",
    "thigh",
    "pelvis",
    "trunk",
    "head_neck",
    "upper_arm",
    "forearm",
    "hand",
}
AXIAL_JOINTS = {
    "ankle_flexion",
    "knee_flexion",
    "hip_flexion",
    "lumbar_flexion",
    "lumbar_side_bend",
    "lumbar_twist",
    "neck_flexion",
    "neck_side_bend",
    "neck_twist",
}
ARM_JOINTS = {
    "clavicle_elevation",
    "shoulder_flexion",
    "shoulder_abduction",
    "shoulder_rotation",
    "elbow_flexion",
    "forearm_pronation",
    "wrist_flexion",
    "wrist_deviation",
}

valid_specs = st.builds(
    BodySpec,
    stature_m=st.floats(1.40, 2.10),
    mass_kg=st.floats(35.0, 160.0),
    sex=st.sampled_from(["male", "female"]),
)
all_percentiles = pytest.mark.parametrize("name", sorted(PERCENTILES))


def _sizes(seg: Segments) -> dict[str, float]:
    return {f.name: getattr(seg, f.name) for f in dataclasses.fields(seg)}


def _mass_total(spec: BodySpec) -> float:
    return sum(
        m.mass_kg * (2 if n in PAIRED_SEGMENTS else 1) for n, m in spec.segment_masses().items()
    )


# --- lengths -----------------------------------------------------------------------------------


def _check_chain(spec: BodySpec) -> None:
    seg = spec.segments()
    assert math.fsum(getattr(seg, n) for n in VERTICAL_CHAIN) == pytest.approx(
        spec.stature_m, abs=1e-9
    )


@all_percentiles
def test_vertical_chain_sums_to_stature_for_every_percentile(name):
    _check_chain(BodySpec.from_percentile(name))


@given(valid_specs)
def test_vertical_chain_sums_to_stature_for_any_valid_body(spec):
    _check_chain(spec)


@given(valid_specs)
def test_every_size_and_landmark_height_is_positive(spec):
    seg = spec.segments()
    assert all(v > 0 for v in _sizes(seg).values())
    assert all(getattr(seg, p) > 0 for p in PROPERTIES)


def test_landmark_heights_follow_the_chain_and_are_ordered():
    spec = BodySpec()
    seg = spec.segments()
    assert seg.knee_height == pytest.approx(seg.ankle_height + seg.shank_length)
    assert seg.hip_height == pytest.approx(seg.knee_height + seg.thigh_length)
    assert seg.neck_joint_height == pytest.approx(
        seg.hip_height + seg.pelvis_height + seg.trunk_length
    )
    assert seg.shoulder_height == pytest.approx(seg.neck_joint_height - seg.shoulder_drop)
    assert seg.hip_height < seg.shoulder_height < seg.neck_joint_height < spec.stature_m
    # The survey's landmarks: trochanterion and acromion, the model's means given stature and
    # mass (ANSUR II men: 0.513 and 0.820 of stature on average).
    marks = spec.landmarks()
    assert seg.hip_height == pytest.approx(marks["hip_height_m"])
    assert seg.shoulder_height == pytest.approx(marks["shoulder_height_m"])
    assert 0.50 < seg.hip_height / spec.stature_m < 0.525
    assert 0.81 < seg.shoulder_height / spec.stature_m < 0.83


def test_the_fixed_ratio_twins_fixed_ratios_remain_an_option():
    spec = BodySpec(proportions="drillis-contini")
    seg = spec.segments()
    # Drillis & Contini put the hip at 0.530 and the shoulder at 0.818 of stature, the elbow
    # joint at 0.632.
    assert seg.hip_height == pytest.approx(0.530 * spec.stature_m)
    assert seg.shoulder_height == pytest.approx(0.818 * spec.stature_m)
    assert spec.elbow_height_m == pytest.approx(0.632 * spec.stature_m)


def test_fixed_ratio_lengths_scale_linearly_with_stature():
    small = BodySpec(stature_m=1.5, mass_kg=70.0, proportions="drillis-contini").segments()
    tall = BodySpec(stature_m=1.8, mass_kg=70.0, proportions="drillis-contini").segments()
    for name, value in _sizes(small).items():
        assert getattr(tall, name) == pytest.approx(1.2 * value, rel=1e-12), name
    for prop in PROPERTIES:
        assert getattr(tall, prop) == pytest.approx(1.2 * getattr(small, prop), rel=1e-12)


def test_mass_widens_the_hips_but_moves_the_joints_by_centimetres_at_most():
    light, heavy = BodySpec(mass_kg=60.0).segments(), BodySpec(mass_kg=120.0).segments()
    # Heavier men of the same stature have broader hips and higher (bulkier) shoulders in the
    # survey; their joint heights differ by less than 3 cm between 60 and 120 kg.
    assert heavy.hip_width > light.hip_width + 0.03
    assert heavy.shoulder_height > light.shoulder_height
    for prop in PROPERTIES:
        assert abs(getattr(heavy, prop) - getattr(light, prop)) < 0.03, prop
    assert BodySpec(mass_kg=50.0, proportions="drillis-contini").segments() == \
        BodySpec(mass_kg=150.0, proportions="drillis-contini").segments()


def test_derived_widths_match_their_definitions():
    seg = BodySpec().segments()
    assert seg.clavicle_length == pytest.approx(seg.shoulder_width / 2)
    assert seg.grip_offset < seg.hand_length
    assert seg.heel_to_ankle < seg.foot_length
    assert seg.shoulder_drop < seg.trunk_length


def test_collision_shapes_do_not_overlap_in_the_standing_posture():
    seg = BodySpec().segments()
    half_shoulder = seg.shoulder_width / 2
    # Hanging upper arms clear the trunk; forearms clear the pelvis and the thighs.
    assert half_shoulder - seg.upper_arm_radius > seg.trunk_width / 2
    assert half_shoulder - seg.forearm_radius > seg.pelvis_width / 2
    assert half_shoulder - seg.forearm_radius > seg.hip_width / 2 + seg.thigh_radius
    # The two thighs and the two shanks do not touch each other.
    assert seg.thigh_radius < seg.hip_width / 2
    assert seg.shank_radius < seg.thigh_radius


# --- masses ------------------------------------------------------------------------------------


@all_percentiles
def test_segment_masses_sum_to_body_mass_for_every_percentile(name):
    spec = BodySpec.from_percentile(name)
    assert _mass_total(spec) == pytest.approx(spec.mass_kg, abs=1e-9)


@given(valid_specs)
def test_segment_masses_sum_to_body_mass_for_any_valid_body(spec):
    masses = spec.segment_masses()
    assert set(masses) == MASS_SEGMENTS
    assert _mass_total(spec) == pytest.approx(spec.mass_kg, abs=1e-9)
    assert all(m.mass_kg > 0 and 0.0 < m.com_fraction < 1.0 for m in masses.values())


def test_segment_masses_are_winter_fractions_and_scale_with_mass():
    light, heavy = BodySpec(mass_kg=50.0), BodySpec(mass_kg=100.0)
    assert heavy.segment_masses()["trunk"].mass_kg == pytest.approx(35.5)
    assert heavy.segment_masses()["thigh"].mass_kg == pytest.approx(10.0)
    for name, m in light.segment_masses().items():
        assert heavy.segment_masses()[name].mass_kg == pytest.approx(2 * m.mass_kg)
        assert heavy.segment_masses()[name].com_fraction == m.com_fraction


# --- percentiles and defaults ------------------------------------------------------------------


def test_default_is_the_50th_percentile_man():
    assert BodySpec() == BodySpec.from_percentile("p50-male")
    assert BodySpec().sex == "male"


def test_percentile_names_are_exactly_the_documented_six():
    assert set(PERCENTILES) == {f"p{p}-{s}" for p in (5, 50, 95) for s in ("male", "female")}


@pytest.mark.parametrize("sex", ["male", "female"])
def test_percentiles_increase_in_stature_and_mass(sex):
    p5, p50, p95 = (BodySpec.from_percentile(f"p{p}-{sex}") for p in (5, 50, 95))
    assert p5.stature_m < p50.stature_m < p95.stature_m
    assert p5.mass_kg < p50.mass_kg < p95.mass_kg
    assert p5.sex == p50.sex == p95.sex == sex


@pytest.mark.parametrize("p", [5, 50, 95])
def test_women_are_smaller_than_men_at_the_same_percentile(p):
    woman = BodySpec.from_percentile(f"p{p}-female")
    man = BodySpec.from_percentile(f"p{p}-male")
    assert woman.stature_m < man.stature_m
    assert woman.mass_kg < man.mass_kg


def test_percentile_values_are_the_documented_ansur_ii_figures():
    assert PERCENTILES["p50-male"][:2] == (1.756, 84.3)
    assert PERCENTILES["p5-female"][:2] == (1.524, 50.8)
    assert PERCENTILES["p95-male"][:2] == (1.869, 110.6)


# --- validation --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "expected"),
    [
        ({"stature_m": 2.5}, ["stature_m", "2.5", "1.40-2.10 m"]),
        ({"stature_m": 1.39}, ["stature_m", "1.39", "1.40-2.10 m"]),
        ({"stature_m": float("nan")}, ["stature_m", "nan", "1.40-2.10 m"]),
        ({"stature_m": float("inf")}, ["stature_m", "inf", "1.40-2.10 m"]),
        ({"stature_m": "1.75"}, ["stature_m", "'1.75'", "1.40-2.10 m"]),
        ({"mass_kg": 200.0}, ["mass_kg", "200.0", "35-160 kg"]),
        ({"mass_kg": 20}, ["mass_kg", "20", "35-160 kg"]),
        ({"mass_kg": float("-inf")}, ["mass_kg", "-inf", "35-160 kg"]),
        ({"sex": "other"}, ["sex", "'other'", "male", "female"]),
        ({"sex": "Male"}, ["sex", "'Male'", "male", "female"]),
    ],
)
def test_invalid_fields_raise_one_line_errors_naming_field_value_and_range(kwargs, expected):
    with pytest.raises(BodySpecError) as info:
        BodySpec(**kwargs)
    message = str(info.value)
    assert "\n" not in message
    for part in expected:
        assert part in message
    assert isinstance(info.value, ValueError)


def test_range_bounds_are_inclusive():
    assert BodySpec(stature_m=1.40, mass_kg=35.0).stature_m == 1.40
    assert BodySpec(stature_m=2.10, mass_kg=160.0).mass_kg == 160.0


def test_unknown_percentile_lists_the_valid_names():
    with pytest.raises(BodySpecError) as info:
        BodySpec.from_percentile("p99-male")
    message = str(info.value)
    assert "p99-male" in message and "\n" not in message
    assert all(name in message for name in PERCENTILES)


def test_spec_is_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        BodySpec().stature_m = 1.9  # type: ignore[misc]


# --- joint limits ------------------------------------------------------------------------------


def test_joint_limit_names_are_exactly_the_documented_set():
    expected = AXIAL_JOINTS | {f"{s}_{j}" for s in ("left", "right") for j in ARM_JOINTS}
    assert set(BodySpec().joint_limits_deg()) == expected


@given(valid_specs)
def test_joint_limits_are_ordered_and_contain_the_neutral_posture(spec):
    for name, (lower, upper) in spec.joint_limits_deg().items():
        assert lower < upper, name
        assert lower <= 0.0 <= upper, name


def test_left_and_right_limits_are_identical():
    limits = BodySpec().joint_limits_deg()
    for joint in ARM_JOINTS:
        assert limits[f"left_{joint}"] == limits[f"right_{joint}"]


def test_joint_limits_have_the_documented_signs():
    limits = BodySpec().joint_limits_deg()
    assert limits["ankle_flexion"] == (-50.0, 20.0)  # plantarflexion exceeds dorsiflexion
    assert limits["knee_flexion"][0] == 0.0 and limits["right_elbow_flexion"][0] == 0.0
    assert limits["right_shoulder_rotation"] == (-90.0, 70.0)  # external > internal
    assert limits["right_wrist_deviation"] == (-20.0, 30.0)  # ulnar > radial
    # The spine's own flexion share leaves the rest of trunk flexion to the hips.
    assert limits["lumbar_flexion"][1] < limits["hip_flexion"][1]


def test_returned_dicts_are_copies():
    spec = BodySpec()
    spec.joint_limits_deg()["knee_flexion"] = (0.0, 1.0)
    spec.segment_masses().pop("trunk")
    assert spec.joint_limits_deg()["knee_flexion"] == (0.0, 135.0)
    assert "trunk" in spec.segment_masses()


IMPAIRED_SHOULDER = (("right_shoulder_flexion", -60.0, 90.0),)


def test_a_restriction_narrows_the_named_joint_and_no_other():
    default, impaired = BodySpec().joint_limits_deg(), BodySpec(
        restrictions=IMPAIRED_SHOULDER).joint_limits_deg()
    assert impaired["right_shoulder_flexion"] == (-60.0, 90.0)
    assert {k: v for k, v in impaired.items() if k != "right_shoulder_flexion"} == {
        k: v for k, v in default.items() if k != "right_shoulder_flexion"}


@pytest.mark.parametrize(("restrictions", "expected"), [
    ((("right_shoulder_flex", -60.0, 90.0),), "'right_shoulder_flex' is not a joint"),
    ((("right_shoulder_flexion", -60.0, 200.0),), "right_shoulder_flexion limit = 200.0 is "
                                                   "outside the valid range -60-180 deg"),
    ((("right_elbow_flexion", 90.0, 30.0),), "the lower is not below the upper"),
    ((("knee_flexion", 0.0, 90.0), ("knee_flexion", 0.0, 80.0)), "restricted twice"),
    ((("knee_flexion", 0.0),), "is not (joint, lower, upper)"),
])
def test_an_impossible_restriction_is_refused_in_one_line(restrictions, expected):
    with pytest.raises(BodySpecError, match=re.escape(expected)) as raised:
        BodySpec(restrictions=restrictions)
    assert "\n" not in str(raised.value)


def test_the_twin_never_flexes_a_restricted_shoulder_past_its_limit():
    import numpy as np

    from ergohandover.twin.evaluate import Evaluator, evaluate

    overhead = np.array([[0.0, 1.95, 0.3]])  # the 50th-percentile man reaches it at ~113°
    free, impaired = (evaluate(overhead, Evaluator(body=b), joints=True)
                      for b in (BodySpec(), BodySpec(restrictions=IMPAIRED_SHOULDER)))
    assert math.degrees(free["q_right_shoulder_flexion"][0]) > 100.0
    assert math.degrees(impaired["q_right_shoulder_flexion"][0]) <= 90.0 + 1e-6
    assert impaired["reba"][0] > free["reba"][0]  # the body makes up for it elsewhere
