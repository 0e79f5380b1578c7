"""The paper's own protocol (experiments/configs/paper.json: 10 Q-learning runs at each of two
wall-clock caps with the paper's episode end, and DQN at the same caps) runs to the end through
run_all, with its caps shrunk to seconds: a manifest, a summary with both agents at both caps, a
comparison of the two, and the figures."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.smoke
@pytest.mark.slow
def test_the_papers_protocol_with_second_long_caps_completes(tmp_path, monkeypatch):
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "cache"))
    results, figures = tmp_path / "results", tmp_path / "figures"
    command = [sys.executable, str(ROOT / "experiments" / "run_all.py"), "--config",
               str(ROOT / "experiments" / "configs" / "paper.json"),
               "--set", "learning.wall_caps_s=[1, 2]", "--set", "baselines.location.budget=wall-2s",
               # a coarse landscape: the part runs first, and the protocol is what is tested
               "--set", "landscape.step=0.02", "--set", "landscape.variants.step=0.04",
               "--only", "learning", "--results", str(results), "--figures", str(figures)]
    out = subprocess.run(command, capture_output=True, text=True, timeout=900)
    assert out.returncode == 0, out.stderr[-3000:]
    manifest = json.loads((results / "learning" / "manifest.json").read_text())
    assert manifest["runs"] == 40 and manifest["part_hash"] and manifest["code_hash"]
    assert manifest["config"]["learning"]["agents"] == ["qlearning", "dqn"]
    summary = pd.read_csv(results / "learning" / "summary.csv")
    assert set(zip(summary["agent"], summary["budget"], strict=True)) == {
        (a, b) for a in ("qlearning", "dqn") for b in ("wall-1s", "wall-2s")}
    assert (summary["n_runs"] == 10).all() and summary["steps"].isna().all()
    runs = pd.read_csv(results / "learning" / "runs.csv")
    assert set(runs["episode_end"]) == {"paper"} and set(runs["stopped_by"]) == {"time_cap"}
    versus = pd.read_csv(results / "learning" / "comparisons.csv")
    assert set(zip(versus["agent"], versus["versus"], strict=True)) == {("qlearning", "dqn")}
    found = pd.read_csv(results / "learning" / "found.csv")
    assert ((found["agent"] == "qlearning") & (found["budget"] == "wall-2s")).any()
    assert {p.name for p in figures.glob("*.png")} >= {"learning_min_score.png",
                                                       "learning_evaluations.png"}
