"""The validation table: cited published numbers, the twin's values at the stated locations,
and an honest `within`."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from ergohandover.study.validation.published import CONDITIONS, MEASURES, validation_table
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import evaluate
from ergohandover.twin.task import TaskSpec

OPTIMUM = np.array([0.0, 1.17, 0.375])


def test_at_least_eight_conditions_from_two_cited_sources():
    assert len(CONDITIONS) >= 8 and len({c.source for c in CONDITIONS}) >= 2
    for c in CONDITIONS:
        assert re.search(r"\(?(19|20)\d\d\)?", c.source), c.source  # a year in every citation
        assert c.low <= c.published <= c.high or c.basis.startswith("acceptable"), c
        assert c.measure in MEASURES and c.location in ("optimum", "knee", "floor")
        if not math.isnan(c.published_sd):
            assert c.low == pytest.approx(c.published - c.published_sd)
            assert c.high == pytest.approx(c.published + c.published_sd)


@pytest.fixture(scope="module")
def table():
    return validation_table(OPTIMUM)


def test_the_twin_is_measured_where_the_condition_says(table):
    task, body = TaskSpec(), BodySpec()
    at = table.set_index("location")
    np.testing.assert_allclose(at.loc["optimum", ["box_x", "box_y", "box_z"]].iloc[0], OPTIMUM)
    floor = at.loc["floor", ["box_y", "box_z"]].iloc[0]
    assert floor["box_y"] == pytest.approx(task.box_height / 2)
    assert floor["box_z"] == pytest.approx(0.236 + task.box_depth / 2)
    assert at.loc["knee", "box_y"].iloc[0] == pytest.approx(body.segments().knee_height)


def test_the_twins_values_are_its_evaluated_angles(table):
    row = evaluate(OPTIMUM[None, :]).iloc[0]
    trunk = table[table["quantity"].str.startswith("trunk inclination")].iloc[0]
    assert trunk["twin"] == pytest.approx(row["trunk_flexion"])
    below = table[table["quantity"].str.startswith("hand height below elbow")]
    expected = (BodySpec().elbow_height_m - OPTIMUM[1]) * 100
    assert below["twin"].to_numpy() == pytest.approx(np.full(len(below), expected))
    reach = table[table["quantity"].str.startswith("horizontal distance")].iloc[0]
    assert reach["twin"] == pytest.approx(OPTIMUM[2] * 100)


def test_within_means_inside_the_published_range(table):
    inside = (table["twin"] >= table["low"]) & (table["twin"] <= table["high"])
    assert (table["within"] == inside).all()
