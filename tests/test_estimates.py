"""The time run_all.py promises at its start is the time the part last took: read from its
manifest in the results folder being written, else from the committed run's (no timing here:
both are read); the learning part costs its own jobs."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pandas as pd
import pytest

from ergohandover.study.config import StudyConfig
from ergohandover.study.learning import part as learning
from ergohandover.study.registry import PARTS

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


def test_the_learning_parts_estimate_is_its_jobs_at_the_last_runs_speeds(tmp_path):
    config = StudyConfig.load(ROOT / "experiments" / "configs" / "default.json", ())
    jobs = learning.plan_jobs(config)
    agents = sorted({job.agent for job in jobs})
    # Runs of every agent at 1,000 steps/s, a search run of 500 steps each.
    runs = pd.DataFrame({"agent": agents, "budget": "b", "run_budget": "b",
                         "steps_per_s": 1_000.0, "evaluations": 500})
    runs.to_csv(tmp_path / "runs.csv", index=False)
    speeds = learning.Speeds.read(tmp_path)
    for job in jobs:
        steps = min(job.steps, 500) if job.kind == "search" and job.oracle_stop else job.steps
        assert learning.job_seconds(job, speeds) == pytest.approx(steps / 1_000)
    total = sum(learning.job_seconds(j, speeds) for j in jobs)
    assert learning.estimate_s(config, 2, tmp_path) == pytest.approx(total / 2)
    # An agent never measured: no estimate, and nothing made up.
    runs[runs["agent"] != "dqn"].to_csv(tmp_path / "runs.csv", index=False)
    assert learning.estimate_s(config, 2, tmp_path) is None
    assert learning.estimate_s(config, 2, tmp_path / "none") is None


def test_the_bar_counts_work_not_runs():
    """At the committed run's speeds a DQN run (stopped at the target) costs many times a
    tabular one to the same budget, and the longest run goes first, so the bar's first minutes
    (DQN first) do not promise hours."""
    config = StudyConfig.load(ROOT / "experiments" / "configs" / "default.json", ())
    speeds = learning.Speeds.read(RESULTS / "learning")
    jobs = learning.plan_jobs(config, speeds)
    cost = {(job.agent, job.budget): learning.job_seconds(job, speeds) for job in jobs}
    assert cost[("dqn", "paper-5min")] > 10 * cost[("qlearning", "paper-5min")]
    assert [learning.job_seconds(j, speeds) for j in jobs] == sorted(
        (learning.job_seconds(j, speeds) for j in jobs), reverse=True)  # the longest first
