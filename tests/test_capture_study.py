"""The capture part's arithmetic: the twin's postures measured back through every format, with
and without published angle errors."""

from __future__ import annotations

import numpy as np
import pytest

from ergohandover.capture import FORMATS
from ergohandover.study.capture.accuracy import column_table, score_table, twin_postures
from ergohandover.twin.evaluate import Evaluator

EXACT = ("h36m17", "zed34", "smpl24")


@pytest.fixture(scope="module")
def handovers():
    evaluator = Evaluator()
    rng = np.random.default_rng(8)
    locations = np.column_stack([rng.uniform(-0.15, 0.15, 40), rng.uniform(0.8, 1.3, 40),
                                 rng.uniform(0.3, 0.55, 40)])
    state, truth = twin_postures(evaluator, locations)
    return evaluator, state, truth


def test_formats_with_a_spine_and_neck_base_measure_the_twin_exactly(handovers):
    evaluator, state, truth = handovers
    table = column_table(evaluator, state, truth)
    assert set(table["format"]) == set(FORMATS)
    exact = table[table["format"].isin(EXACT) & (table["measured"] > 0)]
    assert (exact["max_error_deg"] < 1e-5).all()
    never = table[(table["format"] == "h36m17") & (table["measured"] == 0)]["column"]
    assert set(never) == {"neck_twist", *(f"{s}_wrist_{p}" for s in ("left", "right")
                                         for p in ("flexion", "deviation", "twist"))}


def test_without_error_every_interval_holds_the_twins_score_and_error_costs(handovers):
    evaluator, state, truth = handovers
    table = score_table(evaluator, state, truth, (0.0, 15.0), draws=4, seed=1)
    assert len(table) == len(FORMATS) * 2 * 3
    assert (table["right"] <= table["holds"]).all()
    assert ((table["right_ci_low"] <= table["right"])
            & (table["right"] <= table["right_ci_high"])).all()
    clean = table[(table["angle_sd_deg"] == 0) & table["format"].isin(EXACT)]
    assert (clean["holds"] == 1.0).all()
    zed = table[table["format"] == "zed34"].set_index(["angle_sd_deg", "score"])
    assert zed.loc[(0.0, "paper_postural"), "right"] == 1.0  # ZED sees all the paper reads
    assert zed.loc[(15.0, "paper_postural"), "right"] < 1.0
    for score in ("reba", "rula"):  # the wrists and the shoulder girdle unseen: an interval
        assert zed.loc[(0.0, score), "right"] < zed.loc[(0.0, score), "holds"] == 1.0
    again = score_table(evaluator, state, truth, (0.0, 15.0), draws=4, seed=1)
    assert again.equals(table)  # seeded
