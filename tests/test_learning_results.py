"""The committed learning study: enough targets, agents and paired runs, the three mappings of
the paper's caps, budgets read consistently from one run, corrected comparisons whose verdicts
follow their tests, and a report that says what results/learning/ says."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd
from statsmodels.stats.multitest import multipletests

from ergohandover.search.statistics import verdict
from ergohandover.study.config import StudyConfig

ROOT = Path(__file__).resolve().parents[1]
LEARNING = ROOT / "results" / "learning"
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))

import learning_tables  # noqa: E402
from readme_blocks import REPORT, block  # noqa: E402

CONFIG = StudyConfig.load(ROOT / "experiments" / "configs" / "default.json")


def read(name: str) -> pd.DataFrame:
    return pd.read_csv(LEARNING / name)


def test_the_summary_has_five_targets_five_agents_enough_runs_and_intervals():
    summary = read("summary.csv")
    assert summary["target"].nunique() >= 5
    assert {"qlearning", "randomwalk", "random-draws", "hillclimb", "dqn"} <= set(summary["agent"])
    dqn = summary["agent"] == "dqn"
    assert (summary.loc[~dqn, "n_runs"] >= 100).all() and (summary.loc[dqn, "n_runs"] >= 20).all()
    rate = summary["successes"] / summary["n_runs"]
    assert (rate == summary["success_rate"]).all()
    assert ((summary["ci_low"] >= 0) & (summary["ci_low"] <= rate)
            & (rate <= summary["ci_high"]) & (summary["ci_high"] <= 1)).all()
    assert (summary["censored"] == summary["n_runs"] - summary["successes"]).all()


def test_the_budgets_are_the_papers_caps_under_three_mappings():
    rate = round(3.4e6 / (3 * 3600))  # the paper: ~3.4 M locations in ~3 hours, ~315/s
    assert CONFIG.learning.budgets == {"paper-2min": 120 * rate, "paper-5min": 300 * rate}
    assert set(CONFIG.learning.rates) == {rate, rate / 10, rate * 10}
    assert learning_tables.PAPER_RATE == CONFIG.learning.PAPER_RATE == rate
    summary = read("summary.csv")
    assert set(summary["steps"]) == {3_780, 9_450, 37_800, 94_500, 378_000, 945_000}
    assert set(summary["mapping"]) == {31.5, 315.0, 3150.0}
    assert set(summary.loc[summary["agent"] == "dqn", "mapping"]) == {315.0}
    assert (summary["steps"] == (summary["cap_min"] * 60 * summary["mapping"]).round()).all()


def test_runs_are_paired_and_every_budget_is_read_from_one_run():
    runs = read("runs.csv")
    assert (runs.groupby(["target", "run"])["seed"].nunique() == 1).all()
    assert not runs.duplicated(["target", "agent", "budget", "run"]).any()
    cheap = runs[runs["agent"] != "dqn"]
    assert set(cheap["run_budget"]) == {"paper-5min@3150"}
    assert set(runs.loc[runs["agent"] == "dqn", "run_budget"]) == {"paper-5min"}
    assert set(runs["stopped_by"]) <= {"stop_score", "step_cap"} and runs["oracle_stop"].all()
    # A run that reached the target at a budget has reached it at every larger one, and its
    # best score never rises with the budget.
    ordered = runs.sort_values("steps").groupby(["target", "agent", "run"])
    assert (ordered["reached"].apply(lambda r: r.is_monotonic_increasing)).all()
    assert (ordered["best_score"].apply(lambda b: b.is_monotonic_decreasing)).all()


def test_success_is_reaching_the_target_within_the_budget():
    runs = read("runs.csv")
    assert (runs["best_score"] >= runs["target_score"] - 1e-9).all()
    reached = runs["reached"].astype(bool)
    assert (runs.loc[reached, "best_score"] == runs.loc[reached, "target_score"]).all()
    assert runs.loc[reached, "evaluations_to_target"].le(runs.loc[reached, "steps"]).all()
    assert runs.loc[~reached, "evaluations_to_target"].isna().all()
    assert (runs["evaluations"] <= runs["steps"]).all()


def test_the_full_runs_repeat_their_search_runs_up_to_the_target():
    runs = read("runs.csv").set_index(["target", "agent", "budget", "run"])
    full = read("full_runs.csv")
    assert set(full["stopped_by"]) == {"step_cap"} and (full["run"] < 10).all()
    for row in full.itertuples():
        searched = runs.loc[(row.target, row.agent, row.budget, row.run)]
        assert row.seed == searched["seed"] and row.reached == searched["reached"]
        if row.reached:
            assert row.evaluations_to_target == searched["evaluations_to_target"]


def test_the_comparisons_are_corrected_over_the_family_and_verdicts_follow_them():
    table = read("comparisons.csv")
    config = CONFIG.learning
    for test in ("p_wilcoxon", "p_mcnemar", "p_tost"):
        assert np.allclose(table[f"{test}_holm"], multipletests(table[test], method="holm")[1])
    expected = [verdict(r.p_wilcoxon_holm, r.rank_biserial, r.p_tost_holm, config.margin,
                        config.alpha) for r in table.itertuples()]
    assert list(table["verdict"]) == expected
    assert (table["margin"] == config.margin).all()
    dqn = table["agent"] == "dqn"
    assert (table.loc[~dqn, "n"] >= 100).all() and (table.loc[dqn, "n"] >= 20).all()
    power = read("power.csv")
    assert set(power["n"]) == {config.runs, config.dqn_runs}
    assert (power["family"] == len(table)).all() and power["power"].between(0, 1).all()


def test_the_generated_learning_blocks_are_the_committed_results():
    for name, made in learning_tables.blocks(ROOT / "results").items():
        assert block(name) == made, name


def test_the_baselines_carry_the_box_to_where_the_learner_ended():
    found = read("found.csv")
    spec = CONFIG.baselines.location
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
