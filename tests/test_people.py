"""The people part: the twin beside Kim et al.'s measured handovers. Its committed results agree
with each other and with a recomputation from the committed derived figures (the prediction of
a sample of handovers solved again, the statistics recomputed from the per-handover table);
the split is seeded and keeps the out-of-distribution recordings out of training; a bad fit
setting is refused."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ergohandover.errors import ConfigError
from ergohandover.study.config import StudyConfig
from ergohandover.study.people.beside_people import (
    ANGLES,
    measured_angles,
    measured_handovers,
    predict,
    receiver_body,
    split,
)
from ergohandover.twin.task import TaskSpec

ROOT = Path(__file__).resolve().parents[1]
FOLDER = ROOT / "results" / "people"
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))

import people_tables  # noqa: E402


@pytest.fixture(scope="module")
def table():
    return pd.read_csv(FOLDER / "handovers.csv")


@pytest.fixture(scope="module")
def manifest():
    return json.loads((FOLDER / "manifest.json").read_text())


def test_at_least_900_handovers_are_used_and_the_dropped_are_counted(table, manifest):
    used, dropped = measured_handovers()
    assert len(table) == len(used) == manifest["handovers"] >= 900
    assert sum(manifest["dropped"].values()) == int(dropped.sum()) == 1000 - len(used)
    assert list(table["handover"]) == list(used["handover"])


def test_a_sample_of_predictions_is_solved_again_to_the_committed_angles(table, manifest):
    used, _ = measured_handovers()
    sample = np.random.default_rng(5).choice(len(used), 12, replace=False)
    rows = used.iloc[sample].reset_index(drop=True)
    task = TaskSpec.holding(manifest["config"]["people"]["object"])
    again = predict(rows, [receiver_body(r) for r in rows.itertuples()], task)
    committed = table.iloc[sample].reset_index(drop=True)
    for angle in ANGLES:
        assert np.allclose(again[angle], committed[f"twin_{angle}"], atol=2e-3), angle
    assert (again["hand_error_m"] < 0.01).all()  # every grip reaches the receiver's hand
    assert np.array_equal(measured_angles(rows).round(4).to_numpy(),
                          committed[[f"measured_{a}" for a in ANGLES]].to_numpy())


def test_the_errors_are_those_of_the_per_handover_table(table):
    errors = pd.read_csv(FOLDER / "errors.csv").set_index(["twin", "group", "angle"])
    for twin, prefix in (("default", "twin_"), ("fitted", "fitted_")):
        for group in ("held-out", "out-of-distribution", "train"):
            rows = table[table["split"] == group]
            for angle in ANGLES:
                diff = rows[f"{prefix}{angle}"] - rows[f"measured_{angle}"]
                row = errors.loc[(twin, group, angle)]
                assert row["n"] == len(rows)
                assert row["median_abs_deg"] == pytest.approx(diff.abs().median(), abs=0.01)
                assert row["bias_deg"] == pytest.approx(diff.mean(), abs=0.01)
                assert row["rmse_deg"] == pytest.approx(np.sqrt((diff ** 2).mean()), abs=0.01)
                assert row["median_abs_low"] <= row["median_abs_deg"] <= row["median_abs_high"]


def test_the_location_statistics_are_those_of_the_per_handover_table(table):
    for row in pd.read_csv(FOLDER / "locations.csv").itertuples():
        values = table[row.column]
        assert row.n == values.notna().sum()
        assert row.median == pytest.approx(values.median(), abs=6e-4), row.quantity
        assert row.p5 <= row.p25 <= row.median <= row.p75 <= row.p95


def test_the_recommendation_reads_the_twin_and_people_where_they_received(table):
    advice = pd.read_csv(FOLDER / "recommendation.csv").set_index("score")
    for score in ("reba", "rula", "paper_postural"):
        row = advice.loc[score]
        assert row["n"] == len(table)
        assert row["twin_there_median"] == table[f"twin_{score}"].median()
        assert row["people_lo_median"] == table[f"people_{score}_lo"].median()
        at = (table[f"twin_{score}"] == row["optimum"]).mean()
        assert row["twin_there_at_optimum_share"] == pytest.approx(at, abs=1e-4)
        # Nothing in the twin's landscape scores below its optimum, where people were either.
        assert (table[f"twin_{score}"] >= row["optimum"]).all()
        assert row["distance_p25_m"] <= row["distance_median_m"] <= row["distance_p75_m"]


def test_the_fit_is_reported_as_measured(manifest):
    history = pd.read_csv(FOLDER / "fit.csv")
    factors = manifest["fit_factors"]
    best = history.loc[history["loss_deg"].idxmin()]
    assert {name: best[name] for name in factors} == pytest.approx(factors)
    assert best["loss_deg"] == pytest.approx(manifest["angle_rmse_deg"]["fitted"]["train"],
                                             abs=1e-3)
    study = pd.read_csv(FOLDER / "study_task.csv")
    within = study.groupby("weights")["within"].sum().to_dict()
    assert within == manifest["published_conditions_within"]


def test_the_split_is_seeded_and_keeps_out_of_distribution_out_of_training(table):
    used, _ = measured_handovers()
    groups = split(used, 0.5, 41)
    assert list(groups) == list(table["split"])
    assert not ((used["kind"] == "out-of-distribution") & (groups == "train")).any()
    inside = (used["kind"] == "in-distribution").sum()
    assert (groups == "train").sum() == round(0.5 * inside)
    assert list(split(used, 0.5, 42)) != list(groups)


def test_the_full_headline_is_the_committed_result():
    report = (ROOT / "docs" / "report.md").read_text()
    row = people_tables.blocks(ROOT / "results")["people-headline"]
    assert f"<!-- people-headline -->{row}<!-- /people-headline -->" in report


def test_an_unknown_fit_weight_is_refused():
    with pytest.raises(ConfigError, match=r"people\.fit_weights: 'wrist' is not allowed"):
        StudyConfig.from_dict({"people": {"fit_weights": ["wrist"]}})
