"""The time run_all.py promises at its start is the time the committed run took: each part's
estimate within 30 % of the wall time in its manifest (no timing here: both are read)."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

from ergohandover.study.config import StudyConfig
from ergohandover.study.parts import learning

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "results"


def run_all_module():
    spec = importlib.util.spec_from_file_location("run_all", ROOT / "experiments" / "run_all.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def manifest(part: str) -> dict:
    return json.loads((RESULTS / part / "manifest.json").read_text())


@pytest.mark.parametrize("part", ["landscape", "baselines", "ablations", "participants",
                                  "population", "sensitivity", "robustness",
                                  "personalise"])
def test_each_parts_estimate_is_within_30_percent_of_the_committed_runs_time(part):
    measured = manifest(part)["wall_time_s"]
    estimated = run_all_module().ESTIMATE_S["default"][part]
    assert 0.7 * measured <= estimated <= 1.3 * measured, (part, estimated, measured)


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
