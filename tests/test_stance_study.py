"""The stance part's arithmetic: scoring the headline locations planted and stepping, the
headline comparison, and the comparison under posture error."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ergohandover.study.config import StudyConfig
from ergohandover.study.stance.comparison import headline, scored, under_posture_error

CONFIG = StudyConfig()
NAMED = pd.DataFrame({"worker": "p50-male", "location": ["optimised", "shortest distance",
                                                         "shortest distance"],
                      "start": ["", "start 1", "start 2"], "x": [0.0, 0.0, 0.2],
                      "y": [1.01, 1.12, 1.12], "z": [0.42, 0.60, 0.60]})
EVALUATORS = {s: CONFIG.evaluator(stance=s) for s in ("fixed", "step")}


@pytest.fixture(scope="module")
def table():
    return scored(NAMED, {s: {"p50-male": e} for s, e in EVALUATORS.items()})


def test_every_location_is_scored_once_per_stance_and_only_the_stepping_worker_steps(table):
    assert len(table) == 2 * len(NAMED)
    assert table.groupby("stance").size().to_dict() == {"fixed": 3, "step": 3}
    assert (table.loc[table["stance"] == "fixed", "step_m"] == 0).all()
    # At full reach (0.60 m in front) the stepping worker steps; the optimum is within reach.
    step = table[table["stance"] == "step"].set_index("start")["step_m"]
    assert step["start 1"] > 0 and step["start 2"] > 0


def test_the_headline_comparison_is_optimised_less_shortest_distance(table):
    head = headline(table)
    assert len(head) == 2 * 2 * 3  # stances x starts x scores
    for _, row in head.iterrows():
        assert row["difference"] == row["optimised"] - row["shortest_distance"]
        assert row["beats"] == (row["difference"] < 0)
    # Planted, the optimised location beats both full-reach locations on the paper's score.
    paper = head[(head["stance"] == "fixed") & (head["score"] == "paper_postural")]
    assert paper["beats"].all()


def test_a_headline_without_the_optimised_location_is_empty():
    table = pd.DataFrame({"worker": ["w"], "stance": ["fixed"], "location": ["other"],
                          "start": [""], "paper_postural": [4], "reba": [2], "rula": [3]})
    assert headline(table).empty


def test_without_error_the_comparison_is_the_nominal_difference_and_it_is_seeded(table):
    first = under_posture_error(NAMED, EVALUATORS, (0.0, 5.0), 200, seed=3)
    again = under_posture_error(NAMED, EVALUATORS, (0.0, 5.0), 200, seed=3)
    pd.testing.assert_frame_equal(first, again)
    exact = first[first["angle_sd_deg"] == 0].set_index(["stance", "start", "score"])
    head = headline(table).set_index(["stance", "start", "score"])
    for key, row in exact.iterrows():
        assert row["difference"] == pytest.approx(head.loc[key, "difference"])
        assert row["ci_low"] == pytest.approx(row["ci_high"])  # no error, no spread
    noisy = first[first["angle_sd_deg"] == 5]
    assert np.all(noisy["ci_low"] < noisy["ci_high"])
