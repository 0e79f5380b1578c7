"""One engine for the whole study: the learning part (and the landscape part it reads) run on a
real local Ray instance gives the same step-budgeted runs, bit for bit, as on the local pool."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from ergohandover.study.config import StudyConfig
from ergohandover.study.engines import Engine
from ergohandover.study.registry import part, run_order

ROOT = Path(__file__).resolve().parents[1]
TIMING = ["elapsed_s", "steps_per_s"]  # wall-clock figures: the only columns that may differ


@pytest.mark.slow
def test_the_learning_part_on_ray_repeats_the_local_pool(tmp_path, monkeypatch):
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "cache"))
    config = StudyConfig.load(ROOT / "experiments" / "configs" / "quick.json", (
        'learning.agents=["qlearning", "randomwalk", "random-draws"]', "learning.runs=2",
        "learning.wall_targets=[]", "learning.dqn_targets=[]",
        'learning.targets=[{"name": "paper"}, {"name": "rula", "objective": "rula"}]',
        "baselines.location.target=paper"))
    tables = {}
    for name in ("local", "ray"):
        engine = Engine(name, 2)
        results = tmp_path / name
        with engine.session():  # the learning part after the landscape part it reads
            assert all(part(p).run(config, results, engine) for p in run_order(["learning"]))
        tables[name] = {table: pd.read_csv(results / "learning" / f"{table}.csv")
                        for table in ("runs", "summary", "found", "targets")}
        tables[name]["stats"] = pd.read_csv(results / "landscape" / "stats.csv")
    local, ray = tables["local"], tables["ray"]
    assert len(local["runs"]) == 2 * 3 * 6 * 2  # targets x agents x budgets x runs
    pd.testing.assert_frame_equal(ray["runs"].drop(columns=TIMING),
                                  local["runs"].drop(columns=TIMING))
    for table in ("found", "targets", "stats"):
        pd.testing.assert_frame_equal(ray[table], local[table])
    timing = [c for c in local["summary"] if "per_s" in c]
    pd.testing.assert_frame_equal(ray["summary"].drop(columns=timing),
                                  local["summary"].drop(columns=timing))
