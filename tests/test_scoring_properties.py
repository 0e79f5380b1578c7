"""Properties over many postures: the vectorised scorer equals an independent one-posture
transcription, arms are symmetric, batches do not interact, scores stay in their ranges."""

from __future__ import annotations

import numpy as np
import pytest
import reference_scorer
from conftest import neutral_columns
from hypothesis import given, settings
from hypothesis import strategies as st

from ergohandover.ergonomics import (
    POSTURE_COLUMNS,
    SCORE_COLUMNS,
    Posture,
    ScoringSettings,
    score_postures,
)
from ergohandover.ergonomics.posture import COLUMN_BY_NAME

# Every band edge and threshold in use, so that edge cases are drawn often.
EDGES = [0.0, 2.0, 3.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 90.0, 100.0]
ANGLE = st.one_of(st.sampled_from(EDGES + [-e for e in EDGES]),
                  st.floats(-180.0, 180.0, allow_nan=False))
VALUE = {
    "angle": ANGLE,
    "flag": st.sampled_from([0.0, 1.0]),
    "level": st.sampled_from([0.0, 1.0, 2.0, 3.0]),
    "load": st.one_of(st.sampled_from([0.0, 2.0, 5.0, 10.0]), st.floats(0.0, 30.0)),
}
POSTURE_ROW = st.fixed_dictionaries({c: VALUE[COLUMN_BY_NAME[c].kind] for c in POSTURE_COLUMNS})
THRESHOLD = st.one_of(st.sampled_from([0.0, 10.0, 20.0, 30.0]), st.floats(0.0, 30.0))
SETTINGS = st.builds(
    ScoringSettings,
    neutral_tolerance_deg=st.one_of(st.sampled_from([0.0, 5.0, 15.0]), st.floats(0.0, 15.0)),
    band_edge=st.sampled_from(["lower", "upper"]),
    twist_from_deg=THRESHOLD, side_bend_from_deg=THRESHOLD, abduction_from_deg=THRESHOLD,
    rotation_from_deg=THRESHOLD, shoulder_raise_from_deg=THRESHOLD,
    wrist_deviation_from_deg=THRESHOLD, wrist_twist_from_deg=THRESHOLD,
    twist_side_bend_rule=st.sampled_from(["single", "each"]),
)


def as_posture(rows: list[dict]) -> Posture:
    return Posture({c: np.array([r[c] for r in rows]) for c in POSTURE_COLUMNS})


@settings(max_examples=300, deadline=None)
@given(rows=st.lists(POSTURE_ROW, min_size=1, max_size=8), s=SETTINGS)
@pytest.mark.slow
def test_vectorised_equals_the_independent_scalar_transcription(rows, s):
    scores = score_postures(as_posture(rows), s)
    for i, row in enumerate(rows):
        expected = {**reference_scorer.reba(row, s), **reference_scorer.rula(row, s)}
        got = {k: int(scores[k][i]) for k in expected}
        assert got == expected, {k: (got[k], v) for k, v in expected.items() if got[k] != v}


def mirrored(columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    def swap(name: str) -> str:
        parts = name.split("_")
        other = {"left": "right", "right": "left"}
        return "_".join(other.get(part, part) for part in parts)
    return {swap(k): v for k, v in columns.items()}


def test_left_and_right_are_scored_alike():
    rng = np.random.default_rng(7)
    p = Posture.random(20_000, rng)
    scores = score_postures(p)
    swapped = score_postures(Posture(mirrored(dict(p))))
    for name in SCORE_COLUMNS:
        np.testing.assert_array_equal(swapped[mirrored({name: 0}).popitem()[0]], scores[name],
                                      err_msg=name)


def test_adjustments_apply_to_both_arms():
    for side in ("left", "right"):
        p = Posture(neutral_columns(**{f"{side}_upper_arm_abduction": 40.0,
                                       f"{side}_shoulder_raise": 30.0,
                                       f"{side}_wrist_deviation": 25.0}))
        s = score_postures(p)
        assert s[f"reba_{side}_upper_arm"][0] == 3 and s[f"reba_{side}_wrist"][0] == 2
        assert s[f"rula_{side}_upper_arm"][0] == 3 and s[f"rula_{side}_wrist"][0] == 2
        # The worse arm sets REBA's Table B: upper arm 3, lower arm 1, wrist 2 -> 4.
        assert s["reba_table_b"][0] == 4


def test_a_posture_scores_the_same_alone_and_in_any_batch():
    p = Posture.random(2_000, np.random.default_rng(3))
    whole = score_postures(p)
    order = np.random.default_rng(4).permutation(p.n)
    shuffled = score_postures(p.take(order))
    for name in SCORE_COLUMNS:
        np.testing.assert_array_equal(shuffled[name], whole[name][order])
    for i in (0, 17, 1999):
        single = score_postures(p.take(np.array([i])))
        assert all(single[name][0] == whole[name][i] for name in SCORE_COLUMNS)


def test_scores_stay_within_their_published_ranges():
    s = score_postures(Posture.random(200_000, np.random.default_rng(5)))
    ranges = {"reba": (1, 15), "reba_table_a": (1, 9), "reba_table_b": (1, 9),
              "reba_score_a": (1, 12), "reba_score_b": (1, 12), "reba_score_c": (1, 12),
              "reba_action_level": (0, 4), "rula": (1, 7), "rula_action_level": (1, 4),
              "reba_trunk": (1, 5), "reba_neck": (1, 3), "reba_legs": (1, 4),
              "reba_left_upper_arm": (1, 6), "reba_left_wrist": (1, 3), "rula_neck": (1, 6),
              "rula_trunk": (1, 6), "rula_left_wrist": (1, 4), "paper_postural": (3, 15)}
    for name, (lo, hi) in ranges.items():
        assert lo <= s[name].min() and s[name].max() <= hi, name
    # Random postures reach both ends of the headline scores.
    assert s["reba"].max() == 15 and s["rula"].max() == 7


def test_the_each_rule_adds_one_for_twist_and_one_for_side_bend():
    p = Posture(neutral_columns(trunk_flexion=30.0, trunk_twist=20.0, trunk_side_bend=20.0,
                                neck_flexion=10.0, neck_twist=20.0, neck_side_bend=20.0))
    single = score_postures(p)
    each = score_postures(p, ScoringSettings(twist_side_bend_rule="each"))
    assert (single["reba_trunk"][0], each["reba_trunk"][0]) == (4, 5)
    assert (single["reba_neck"][0], each["reba_neck"][0]) == (2, 3)


def test_reba_ab_is_table_a_plus_table_b():
    s = score_postures(Posture.random(10_000, np.random.default_rng(9)))
    np.testing.assert_array_equal(s["reba_ab"], s["reba_table_a"] + s["reba_table_b"])
    # Table C flattens: many distinct (A, B) sums share one REBA score.
    assert len(np.unique(s["reba_ab"])) > 10
