"""Package-level promises: the scoring engine imports numpy only; the whole study runs."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from ergohandover.study.registry import QUESTIONS

ROOT = Path(__file__).resolve().parents[1]


def test_the_ergonomics_engine_imports_no_simulator_and_no_pandas():
    code = ("import sys, ergohandover.ergonomics; "
            "print(sorted(m for m in ('pybullet', 'pandas', 'torch', 'gymnasium') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


@pytest.mark.smoke
@pytest.mark.slow
def test_run_all_quick_produces_every_table_and_figure_and_resumes(tmp_path, monkeypatch):
    # As a reviewer does to prove nothing is stale: no results/ and no paper_figs/ at all.
    results, figures = tmp_path / "results" / "quick", tmp_path / "paper_figs" / "quick"
    cache = tmp_path / "cache"
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(cache))
    command = [sys.executable, str(ROOT / "experiments" / "run_all.py"), "--quick",
               "--results", str(results), "--figures", str(figures)]
    documents = {page: page.read_bytes() for page in (ROOT / "README.md", *ROOT.glob("docs/*.md"))}
    # The timeouts guard against a hang, not a time target (a shared machine's speed varies).
    first = subprocess.run(command, capture_output=True, text=True, timeout=1800)
    assert first.returncode == 0, first.stderr[-2000:]
    # A run into a folder of its own never rewrites the documents (they quote the committed run).
    assert [p.name for p, text in documents.items() if p.read_bytes() != text] == []
    for part in ("landscape", "learning", "baselines", "ablations", "participants",
                 "population"):
        manifest = json.loads((results / part / "manifest.json").read_text())
        assert manifest["part_hash"] and manifest["versions"]["numpy"]
    # Each part's manifest lists what it wrote: only what its registry entry declares.
    for question in QUESTIONS:
        wrote = json.loads((results / question.name / "manifest.json").read_text())["wrote"]
        assert set(wrote) <= set(question.writes), question.name
    assert {p.name for p in figures.glob("*.png")} >= {
        "score_distribution.png", "learning_min_score.png", "learning_best_so_far.png",
        "learning_evaluations.png", "learning_success.png", "learning_rollouts.png",
        "baselines_boxplot.png", "participants.png", "population_penalties.png",
        "population_optima.png"}
    tables = (results / "tables.md").read_text()
    for heading in ("exhaustive landscape", "Learning", "Optimised vs shortest",
                    "Simulated participants", "Population: one-size vs personalised",
                    "Ablation: human IK"):
        assert heading in tables
    runs = pd.read_csv(results / "learning" / "runs.csv")
    assert set(runs["agent"]) == {"qlearning", "qlearning-adaptive", "dqn", "randomwalk",
                                  "random-draws", "hillclimb"}
    assert (runs["best_score"] >= runs["target_score"]).all()
    assert set(runs["stopped_by"]) <= {"step_cap", "stop_score"}  # runs stop at the target
    assert list(cache.glob("landscapes/*.npz")), "the study's landscapes go to the cache"
    # A second run reuses every finished part.
    second = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert second.returncode == 0
    for part in ("landscape", "learning", "baselines", "ablations", "participants",
                 "population"):
        assert f"[{part}] reusing finished results" in second.stdout
    # An empty cache (a fresh clone): a part that needs the landscape sweeps it again and
    # gets the same numbers.
    def numbers(table: Path) -> pd.DataFrame:  # all but the planner's wall time
        return pd.read_csv(table).drop(columns="planning_s")

    baselines = numbers(results / "baselines" / "baselines.csv")
    for path in cache.glob("landscapes/*.npz"):
        path.unlink()
    third = subprocess.run([*command, "--only", "baselines", "--force"], capture_output=True,
                           text=True, timeout=600)
    assert third.returncode == 0, third.stderr[-2000:]
    assert "sweep" in third.stderr
    pd.testing.assert_frame_equal(numbers(results / "baselines" / "baselines.csv"), baselines)
