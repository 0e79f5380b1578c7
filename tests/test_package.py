"""Package-level promises: the scoring engine imports numpy only; the example run works."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_the_ergonomics_engine_imports_no_simulator_and_no_pandas():
    code = ("import sys, ergohandover.ergonomics; "
            "print(sorted(m for m in ('pybullet', 'pandas', 'torch', 'gymnasium') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


def test_run_all_writes_scores_with_a_manifest(tmp_path):
    subprocess.run([sys.executable, str(ROOT / "experiments" / "run_all.py"), "--results",
                    str(tmp_path)], check=True, capture_output=True, timeout=120)
    folder = tmp_path / "example_scores"
    manifest = json.loads((folder / "manifest.json").read_text())
    assert manifest["result"] == "scores.csv"
    assert manifest["config"]["settings"]["band_edge"] == "lower"
    assert manifest["versions"]["numpy"] and manifest["wall_time_s"] >= 0
    assert (folder / "scores.csv").read_text().count("\n") == 4
