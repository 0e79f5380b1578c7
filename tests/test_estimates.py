"""The time run_all.py promises at its start is the time the part last took: read from its
manifest in the results folder being written, else from the committed run's (no timing here:
both are read); the learning part costs its own jobs."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

from ergohandover.study.config import StudyConfig
from ergohandover.study.parts import PARTS, learning

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "results"


def run_all_module():
    spec = importlib.util.spec_from_file_location("run_all", ROOT / "experiments" / "run_all.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def manifest(part: str) -> dict:
    return json.loads((RESULTS / part / "manifest.json").read_text())


def test_each_parts_estimate_is_its_last_measured_time(tmp_path):
    run_all = run_all_module()
    config = StudyConfig()
    # Nothing in a new results folder: the committed run's time.
    for part in PARTS:
        if part != "learning":
            assert run_all.estimate(part, tmp_path, "default", config, 2) == pytest.approx(
                manifest(part)["wall_time_s"]), part
    # A run of the folder's own wins over the committed one.
    (tmp_path / "stance").mkdir()
    (tmp_path / "stance" / "manifest.json").write_text(json.dumps({"wall_time_s": 123.5}))
    assert run_all.estimate("stance", tmp_path, "default", config, 2) == 123.5
    # Never measured: no number is made up.
    assert run_all.estimate("figures", tmp_path, "default", config, 2) is None
    run_all.COMMITTED["quick"] = tmp_path / "never-run"  # this module object's own
    assert run_all.estimate("stance", tmp_path / "none", "quick", config, 2) is None


def test_the_learning_parts_estimate_from_its_jobs_is_within_30_percent():
    recorded = manifest("learning")
    config = StudyConfig.load(ROOT / "experiments" / "configs" / "default.json", ())
    estimated = learning.estimate_s(config, recorded["engine"]["workers"])
    measured = recorded["wall_time_s"]
    assert 0.7 * measured <= estimated <= 1.3 * measured, (estimated, measured)


def test_the_bar_counts_work_not_runs():
    """A DQN run (stopped at the target, ~13,000 steps on average) is costed at over 20 times
    a tabular one to the same budget, so the bar's first minutes (DQN first) do not promise
    hours."""
    config = StudyConfig.load(ROOT / "experiments" / "configs" / "default.json", ())
    jobs = learning.plan_jobs(config)
    cost = {(job.agent, job.budget): learning.job_seconds(job) for job in jobs}
    assert cost[("dqn", "paper-5min")] > 20 * cost[("qlearning", "paper-5min")]
    assert [learning.job_seconds(j) for j in jobs] == sorted(
        (learning.job_seconds(j) for j in jobs), reverse=True)  # the longest first
