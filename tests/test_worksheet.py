"""A rater's worksheet: the tables from item scores are the angle scorers' own, and a sheet
with a missing or impossible item is refused in one line."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from ergohandover.ergonomics import Posture, PostureError, ScoringSettings, score_postures
from ergohandover.ergonomics.worksheet import item_columns, score_items

REBA = importlib.import_module("ergohandover.ergonomics.reba")
RULA = importlib.import_module("ergohandover.ergonomics.rula")
PAPER = importlib.import_module("ergohandover.ergonomics.paper_score")


def items_of(posture: Posture) -> dict[str, np.ndarray]:
    settings = ScoringSettings()
    return {**REBA.items(posture, settings), **RULA.items(posture, settings)}


def test_items_of_any_posture_give_the_angle_scorers_tables_and_scores():
    posture = Posture.random(20_000, np.random.default_rng(11))
    every = score_postures(posture)
    from_items = score_items(items_of(posture))
    assert {"reba", "reba_table_a", "reba_score_c", "rula", "rula_score_d"} <= set(from_items)
    for name, values in from_items.items():
        np.testing.assert_array_equal(values, every[name], err_msg=name)
    paper = PAPER.paper_from_items(PAPER.items(posture))
    np.testing.assert_array_equal(paper["paper_postural"], every["paper_postural"])


def test_one_arm_stands_for_both_and_a_sheet_may_come_alone():
    posture = Posture.random(500, np.random.default_rng(2))
    items = {k: v for k, v in REBA.items(posture, ScoringSettings()).items()
             if "_right_" not in k}
    one_arm = {k.replace("_left_", "_"): v for k, v in items.items()}
    scored = score_items(one_arm)
    assert not any(name.startswith("rula") for name in scored)
    expected = REBA.reba_from_items({**items, **{k.replace("_left_", "_right_"): v
                                                 for k, v in items.items() if "_left_" in k}})
    np.testing.assert_array_equal(scored["reba"], expected["reba"])


def test_table_c_of_a_filled_sheet():
    """Hignett & McAtamney (2000), Table C: Score A 6 with Score B 9 is 10; + activity 1."""
    sheet = {"reba_trunk": [3], "reba_neck": [2], "reba_legs": [2], "reba_load": [1],
             "reba_upper_arm": [4], "reba_lower_arm": [2], "reba_wrist": [3],
             "reba_coupling": [2], "reba_activity": [1]}
    scored = score_items(sheet)
    # Table A (3, 2, 2) = 5, + load 1 = 6; Table B (4, 2, 3) = 7, + coupling 2 = 9.
    assert (scored["reba_table_a"][0], scored["reba_score_a"][0]) == (5, 6)
    assert (scored["reba_table_b"][0], scored["reba_score_b"][0]) == (7, 9)
    assert (scored["reba_score_c"][0], scored["reba"][0]) == (10, 11)


@pytest.mark.parametrize(("change", "message"), [
    ({"reba_trunk": [6]}, "row 1, column 'reba_trunk': 6 is not allowed (expected an integer 1-5)"),
    ({"reba_wrist": [1.5]}, "column 'reba_wrist': 1.5 is not allowed (expected an integer 1-3)"),
    ({"reba_coupling": [float("nan")]}, "column 'reba_coupling': nan is not allowed"),
    ({"reba_left_wrist": [1]}, "column 'reba_wrist' and column 'reba_left_wrist' both given"),
])
def test_an_impossible_item_is_refused_naming_row_and_column(change, message):
    sheet = {"reba_trunk": [1], "reba_neck": [1], "reba_legs": [1], "reba_load": [0],
             "reba_upper_arm": [1], "reba_lower_arm": [1], "reba_wrist": [1],
             "reba_coupling": [0], "reba_activity": [0], **change}
    with pytest.raises(PostureError, match=message.replace("(", r"\(").replace(")", r"\)")):
        score_items(sheet)


def test_a_sheet_missing_an_item_or_no_sheet_at_all_is_refused():
    with pytest.raises(PostureError, match="missing RULA item column 'rula_neck'"):
        score_items({c: [1] for c in item_columns("rula") if c not in (
            "rula_neck",) and "_left_" not in c and "_right_" not in c})
    with pytest.raises(PostureError, match="no worksheet item columns"):
        score_items({"trunk_flexion": [10.0]})
