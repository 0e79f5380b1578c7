"""Validation at the boundary: postures and settings are rejected with one-line messages."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import neutral_columns

from ergohandover.ergonomics import (
    REQUIRED_COLUMNS,
    Posture,
    PostureError,
    ScoringSettings,
    SettingsError,
)


def test_optional_columns_take_their_defaults():
    p = Posture(neutral_columns())
    assert p["bilateral_support"][0] == 1 and p["hands_above_neck"][0] == 0
    assert p["load_kg"][0] == 0 and p["coupling"][0] == 0 and p["left_arm_supported"][0] == 0


def test_the_callers_arrays_stay_writable_and_the_posture_does_not():
    cols = neutral_columns()
    p = Posture(cols)
    cols["trunk_flexion"][0] = 42.0  # the caller's own array is still writable
    with pytest.raises(ValueError):
        p["neck_flexion"][0] = 1.0


@pytest.mark.parametrize(("column", "value", "expected"), [
    ("trunk_flexion", np.nan, "row 1, column 'trunk_flexion': nan is not allowed"),
    ("left_elbow_flexion", np.inf, "row 1, column 'left_elbow_flexion': inf"),
    ("neck_twist", 181.0, "within -180..180"),
    ("coupling", 4.0, "column 'coupling': 4 is not allowed (expected an integer 0-3)"),
    ("coupling", 1.5, "column 'coupling': 1.5"),
    ("activity", -1.0, "column 'activity'"),
    ("load_kg", -0.5, "column 'load_kg': -0.5 is not allowed (expected a finite load"),
    ("bilateral_support", 2.0, "column 'bilateral_support': 2 is not allowed (expected 0 or 1)"),
])
def test_bad_values_are_named_with_row_column_and_value(column, value, expected):
    with pytest.raises(PostureError) as info:
        Posture(neutral_columns(**{column: value}))
    assert expected in str(info.value)
    assert "\n" not in str(info.value)
    assert info.value.column == column and info.value.row == 1


def test_a_missing_required_column_is_named():
    cols = neutral_columns()
    del cols["right_wrist_twist"]
    with pytest.raises(PostureError, match="missing required column 'right_wrist_twist'"):
        Posture(cols)
    assert "right_wrist_twist" in REQUIRED_COLUMNS


def test_columns_of_different_lengths_are_rejected():
    cols = neutral_columns()
    cols["trunk_flexion"] = np.zeros(3)
    with pytest.raises(PostureError, match="one length"):
        Posture(cols)


@pytest.mark.parametrize(("field", "value", "message"), [
    ("neutral_tolerance_deg", 20.0, "neutral_tolerance_deg = 20.0 is outside the valid range "
                                    "0-15 deg"),
    ("twist_from_deg", 31.0, "twist_from_deg = 31.0 is outside the valid range 0-30 deg"),
    ("abduction_from_deg", -1.0, "abduction_from_deg = -1.0 is outside"),
    ("wrist_twist_from_deg", float("nan"), "wrist_twist_from_deg = nan is outside"),
    ("band_edge", "middle", "band_edge = 'middle' is not allowed (use 'lower' or 'upper')"),
    ("twist_side_bend_rule", "both", "twist_side_bend_rule = 'both' is not allowed"),
])
def test_settings_outside_their_range_are_rejected(field, value, message):
    with pytest.raises(SettingsError) as info:
        ScoringSettings(**{field: value})
    assert message in str(info.value)


def test_no_count_from_default_is_above_30_degrees():
    s = ScoringSettings()
    from dataclasses import fields

    for f in fields(s):
        if f.name.endswith("_from_deg"):
            assert 0 <= getattr(s, f.name) <= 30
