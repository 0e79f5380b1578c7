"""The committed manikins and accommodation results hold together: each table agrees with the
others and with the definitions in docs/workload.md."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ergohandover.workload import WORKLOAD_COLUMNS
from ergohandover.workload.manikins import MANIKINS

RESULTS = Path(__file__).resolve().parents[1] / "results"
ACCOMMODATION = RESULTS / "accommodation"


@pytest.fixture(scope="module")
def accommodation():
    part = json.loads((ACCOMMODATION / "manifest.json").read_text())["config"]["accommodation"]
    return (part, pd.read_csv(ACCOMMODATION / "cells.csv"),
            pd.read_csv(ACCOMMODATION / "locations.csv"),
            pd.read_csv(ACCOMMODATION / "zone.csv").set_index("kind"),
            pd.read_csv(ACCOMMODATION / "workers.csv"))


def test_the_workforce_is_the_configured_one(accommodation):
    part, _, at, _, workers = accommodation
    assert len(workers) == part["size"] >= 1000 and workers["worker"].is_unique
    assert (workers["sex"] == "female").sum() == round(part["size"] * part["female_share"])
    assert (at["workers"] == part["size"]).all()


def test_the_recommended_share_is_its_workers_mean(accommodation):
    part, _, at, _, workers = accommodation
    rec = at[at["location"] == "nominal optimum"].iloc[0]
    suited = (workers["reba"] <= part["reba_max"]) & (workers["rula"] <= part["rula_max"]) \
        & workers["feasible"].astype(bool)
    assert (suited == workers["exact"].astype(bool)).all()
    assert rec["exact_share"] == pytest.approx(suited.mean(), abs=1e-4)
    assert rec["measured_share"] == pytest.approx(workers["chance"].mean(), abs=1e-4)
    assert rec["measured_low"] <= rec["measured_share"] <= rec["measured_high"]
    assert workers["chance"].min() >= 0 and workers["chance"].max() <= 1


def test_the_zone_is_the_cells_that_reach_the_share(accommodation):
    part, cells, _, zone, _ = accommodation
    for kind in ("exact", "measured"):
        row = zone.loc[kind]
        inside = cells[f"{kind}_share"] >= part["share"]
        assert int(row["cells"]) == int(inside.sum())
        assert int(row["cells_sure"]) == int((cells[f"{kind}_low"] >= part["share"]).sum())
        assert row["best_share"] == pytest.approx(cells[f"{kind}_share"].max(), abs=1e-4)
        if int(row["cells"]) == 0:
            assert pd.isna(row["box_cells"])
            continue
        box = cells[np.logical_and.reduce([
            cells[a].between(row[f"box_{a}_min"] - 1e-6, row[f"box_{a}_max"] + 1e-6)
            for a in "xyz"])]
        assert len(box) == int(row["box_cells"]) and (box[f"{kind}_share"] >= part["share"]).all()
    # A worker who cannot take the box is not suited: no share exceeds who can take it.
    assert (cells["exact_share"] <= cells["feasible_share"] + 1e-9).all()
    assert (cells["measured_share"] <= cells["feasible_share"] + 1e-9).all()


def test_every_manikin_at_every_headline_location():
    table = pd.read_csv(RESULTS / "manikins" / "manikins.csv")
    named = pd.read_csv(RESULTS / "robustness" / "locations.csv")["location"].unique()
    assert set(table["manikin"]) == set(MANIKINS)
    assert len(table) == len(MANIKINS) * len(named)
    feasible = table["feasible"].astype(bool)
    assert table.loc[feasible, list(WORKLOAD_COLUMNS)].notna().all().all()
    assert table.loc[~feasible, list(WORKLOAD_COLUMNS)].isna().all().all()
    # The same location, lifted the same way: the lifting equation does not depend on the body;
    # the back load grows with the body's mass.
    at = table[feasible & (table["location"] == "nominal optimum")].set_index("manikin")
    assert at["niosh_li"].nunique() == 1
    assert list(at.sort_values("mass_kg")["back_compression_n"]) == sorted(
        at["back_compression_n"])
