"""The shift question's committed results: the fatigue model's endurance times beside the
published power laws, recomputed from the model, and the report's table from them."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ergohandover.study.config import StudyConfig
from ergohandover.study.shift.part import endurance_table
from ergohandover.workload.fatigue import JOINTS, endurance_time, power_law_endurance

ROOT = Path(__file__).resolve().parents[1]
SHIFT = ROOT / "results" / "shift"


def test_the_reference_table_is_the_models_closed_form_beside_the_power_law():
    table = pd.read_csv(SHIFT / "reference.csv")
    loads = StudyConfig().shift.reference_loads
    assert set(table["joint"]) == set(JOINTS) and len(table) == len(JOINTS) * len(loads)
    for row in table.itertuples():
        assert row.model_s == pytest.approx(float(endurance_time(row.load, row.joint)))
        assert row.power_law_s == pytest.approx(float(power_law_endurance(row.load, row.joint)))
    assert table["within_band"].all()
    # The published check: the shoulder's 274 s at 20 % and 57.7 s at 50 % of strength.
    shoulder = table[table["joint"] == "shoulder"].set_index("load")["model_s"]
    assert shoulder[0.2] == pytest.approx(274, rel=0.005)
    assert shoulder[0.5] == pytest.approx(57.7, rel=0.005)


def test_the_curves_fall_with_the_load_and_match_the_table():
    curves = pd.read_csv(SHIFT / "curves.csv")
    for _, table in curves.groupby("joint"):
        held = table[table["load"] > table["never_fails_below"]]
        assert (np.diff(held["model_s"]) < 0).all() and (np.diff(table["power_law_s"]) < 0).all()
    again = endurance_table(sorted(curves["load"].unique()))
    pd.testing.assert_frame_equal(curves.reset_index(drop=True), again, check_dtype=False)


def test_the_reports_table_is_the_committed_results():
    sys.path.insert(0, str(ROOT / "experiments" / "analysis"))
    try:
        import shift_tables
        from readme_blocks import readme_block
    finally:
        sys.path.pop(0)
    report = (ROOT / "docs" / "report.md").read_text()
    for name, text in shift_tables.blocks(ROOT / "results").items():
        assert readme_block(report, name) == text, name


def test_the_shift_locations_compare_the_posture_optimum_with_the_shifts_best():
    table = pd.read_csv(SHIFT / "locations.csv")
    part = StudyConfig().shift
    pairs = {(r, h) for r in part.rates_per_min for h in part.holds_s if h < 60 / r}
    assert set(zip(table["rate_per_min"], table["hold_s"], strict=True)) == pairs
    kept = table["shift_capacity_end"].fillna(-1.0)
    for _, rows in table.groupby(["rate_per_min", "hold_s"]):
        found = rows.set_index("location")
        optimum = found.loc["posture-optimal"]
        same = found.loc["best for the shift at the optimal score"]
        alone = found.loc["best for the shift alone"]
        assert same["paper_postural"] == optimum["paper_postural"]
        assert alone["paper_postural"] >= optimum["paper_postural"]
        lasts = pd.Series(kept.loc[rows.index].to_numpy(), index=rows["location"])
        assert lasts["best for the shift alone"] >= lasts[
            "best for the shift at the optimal score"] >= lasts["posture-optimal"]
    # At one location the shift takes more the faster the handovers come.
    optimum = table[(table["location"] == "posture-optimal") & (table["hold_s"] == 3.0)]
    assert (np.diff(optimum.sort_values("rate_per_min")["shift_capacity_end"].fillna(-1)) <= 0
            ).all()


def test_the_trace_ends_where_the_locations_table_says():
    trace = pd.read_csv(SHIFT / "trace.csv")
    table = pd.read_csv(SHIFT / "locations.csv")
    assert {"posture-optimal"} < set(trace["location"])
    assert {n for n in trace["location"] if n != "posture-optimal"} == {
        n for n in table["location"] if n.startswith("shortest distance")}
    for (rate, hold, where, joint), curve in trace.groupby(
            ["rate_per_min", "hold_s", "location", "joint"]):
        row = table[(table["rate_per_min"] == rate) & (table["hold_s"] == hold)
                    & (table["location"] == where)].iloc[0]
        curve = curve.sort_values("minute")
        assert curve["minute"].iloc[-1] == 60 * row["hours"]
        end = row[f"{joint}_capacity_end"]
        if np.isnan(end):  # the joint failed: its curve stops there, within a cycle
            failed, cycle = row[f"{joint}_failure_min"], 1 / rate
            assert curve.loc[curve["minute"] < failed - cycle, "capacity"].notna().all()
            assert curve.loc[curve["minute"] > failed + cycle, "capacity"].isna().all()
            assert curve["capacity"].isna().iloc[-1]
        else:
            assert curve["capacity"].iloc[-1] == pytest.approx(end)
            assert (curve["capacity"].to_numpy() >= end - 1e-9).all()  # it only falls


def test_the_workforce_over_a_shift_is_a_share_with_its_interval_and_harder_shifts_serve_fewer():
    table = pd.read_csv(ROOT / "results" / "accommodation" / "shift.csv")
    zone = pd.read_csv(ROOT / "results" / "accommodation" / "shift_zone.csv")
    part = StudyConfig().shift
    plans = {(p.rate_per_min, p.hold_s) for p in part.plans()}
    assert set(zip(table["rate_per_min"], table["hold_s"], strict=True)) == plans
    assert set(zip(zone["rate_per_min"], zone["hold_s"], strict=True)) == plans
    assert (table["keep"] == part.keep).all() and (table["workers"] == 1000).all()
    assert ((table["kept_low"] <= table["kept_share"]) & (table["kept_share"]
                                                          <= table["kept_high"])).all()
    assert (table["kept_share"] + table["fails_share"] <= 1 + 1e-9).all()
    for _, rows in table.groupby(["location", "hold_s"]):
        rows = rows.sort_values("rate_per_min")
        assert (np.diff(rows["kept_share"]) <= 1e-9).all()  # more handovers never keep more
    for _, rows in zone.groupby("hold_s"):
        assert (np.diff(rows.sort_values("rate_per_min")["cells"]) <= 0).all()
