"""The committed learning study: enough targets and agents, intervals, independent runs, and a
report that says what results/learning/ says."""

from __future__ import annotations

import sys
from pathlib import Path

import pandas as pd

from ergohandover.study.config import StudyConfig

ROOT = Path(__file__).resolve().parents[1]
LEARNING = ROOT / "results" / "learning"
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))

import learning_tables  # noqa: E402
from readme_blocks import REPORT, block  # noqa: E402


def read(name: str) -> pd.DataFrame:
    return pd.read_csv(LEARNING / name)


def test_the_summary_has_five_targets_five_agents_and_intervals():
    summary = read("summary.csv")
    assert summary["target"].nunique() >= 5
    assert {"qlearning", "randomwalk", "random", "hillclimb", "dqn"} <= set(summary["agent"])
    assert (summary["n_runs"] >= 10).all()
    rate = summary["successes"] / summary["n_runs"]
    assert (rate == summary["success_rate"]).all()
    assert ((summary["ci_low"] >= 0) & (summary["ci_low"] <= rate)
            & (rate <= summary["ci_high"]) & (summary["ci_high"] <= 1)).all()
    assert (summary["censored"] == summary["n_runs"] - summary["successes"]).all()


def test_the_paper_matched_budgets_are_the_papers_caps_at_its_evaluation_rate():
    config = StudyConfig.load(ROOT / "experiments" / "configs" / "default.json")
    rate = round(3.4e6 / (3 * 3600))  # the paper: ~3.4 M locations in ~3 hours, ~315/s
    assert config.learning.budgets == {"paper-2min": 120 * rate, "paper-5min": 300 * rate}
    assert set(read("summary.csv").dropna(subset=["steps"])["steps"]) == {37_800, 94_500}


def test_every_run_is_its_own_and_none_stopped_at_the_optimum():
    runs, traces = read("runs.csv"), read("traces.csv")
    assert not runs.duplicated(["agent", "target", "seed"]).any()
    assert set(runs["stopped_by"]) <= {"step_cap", "time_cap"}
    assert not runs["oracle_stop"].any()
    keys = ["target", "agent", "budget", "run"]
    distinct = {tuple(map(tuple, t.drop(columns=[*keys, "time_s"]).to_numpy()))
                for _, t in traces.groupby(keys)}
    assert len(distinct) == len(runs)  # no two runs' traces are the same


def test_success_is_reaching_the_target_and_never_beyond_it():
    runs = read("runs.csv")
    assert (runs["best_score"] >= runs["target_score"]).all()
    reached = runs["reached"].astype(bool)
    assert (runs.loc[reached, "best_score"] == runs.loc[reached, "target_score"]).all()
    assert runs.loc[reached, "evaluations_to_target"].le(runs.loc[reached, "evaluations"]).all()
    assert runs.loc[~reached, "evaluations_to_target"].isna().all()


def test_the_generated_learning_blocks_are_the_committed_results():
    for name, made in learning_tables.blocks(ROOT / "results").items():
        assert block(name) == made, name


def test_the_baselines_carry_the_box_to_where_the_learner_ended():
    found = read("found.csv")
    spec = StudyConfig.load(ROOT / "experiments" / "configs" / "default.json").baselines.location
    row = found[(found["target"] == spec.target) & (found["agent"] == spec.agent)
                & (found["budget"] == spec.budget)].iloc[0]
    table = pd.read_csv(ROOT / "results" / "baselines" / "baselines.csv")
    optimised = table[table["method"] == "optimised"]
    assert (optimised[["x", "y", "z"]].round(6) == row[["x", "y", "z"]].round(6).to_numpy()
            ).all().all()
    assert (optimised["argmin_x"] == row["argmin_x"]).all()
    report = REPORT.read_text()
    assert (f"Q-learning's ten runs at the {spec.budget} budget found, ({row['x']:.3f}, "
            f"{row['y']:.3f}, {row['z']:.3f}) m") in " ".join(report.split())
