"""Package-level promises: the scoring engine imports numpy only; the whole study runs."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_the_ergonomics_engine_imports_no_simulator_and_no_pandas():
    code = ("import sys, ergohandover.ergonomics; "
            "print(sorted(m for m in ('pybullet', 'pandas', 'torch', 'gymnasium') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


@pytest.mark.smoke
def test_run_all_quick_produces_every_table_and_figure_and_resumes(tmp_path):
    results, figures = tmp_path / "results", tmp_path / "figs"
    command = [sys.executable, str(ROOT / "experiments" / "run_all.py"), "--quick",
               "--results", str(results), "--figures", str(figures)]
    first = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert first.returncode == 0, first.stderr[-2000:]
    for part in ("landscape", "learning", "baselines", "ablations", "participants"):
        manifest = json.loads((results / part / "manifest.json").read_text())
        assert manifest["part_hash"] and manifest["versions"]["numpy"]
    assert {p.name for p in figures.glob("*.png")} >= {
        "score_distribution.png", "learning_min_score.png", "learning_best_so_far.png",
        "baselines_boxplot.png", "participants.png"}
    tables = (results / "tables.md").read_text()
    for heading in ("exhaustive landscape", "Learning", "Optimised vs shortest",
                    "Simulated participants", "Ablations"):
        assert heading in tables
    runs = pd.read_csv(results / "learning" / "runs.csv")
    assert set(runs["agent"]) == {"qlearning", "random", "hillclimb", "dqn"}
    assert (runs["best_score"] >= runs["global_min"]).all()
    # A second run reuses every finished part.
    second = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert second.returncode == 0
    for part in ("landscape", "learning", "baselines", "ablations", "participants"):
        assert f"[{part}] reusing finished results" in second.stdout
    # Without the landscape file (not committed), the landscape part is not finished.
    (results / "landscape" / "landscape.npz").unlink()
    from ergohandover.study.parts import is_done, part_config

    config = json.loads((ROOT / "experiments" / "configs" / "quick.json").read_text())
    assert not is_done(results / "landscape", part_config(config, "landscape"))
    assert is_done(results / "learning", part_config(config, "learning"))
