"""The learning study's parts: the random walk, the lexicographic objective, targets, greedy
rollouts, the statistics, the study's runs (paired seeds, determinism) and the part itself on
the quick configuration."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from synthetic import CENTRE, bowl_env, bowl_landscape, cached_bowl, flat

from ergohandover.envs import HandoverEnv, LandscapeScores
from ergohandover.envs.scores import LEXICOGRAPHIC, objective_values
from ergohandover.search.qlearning import QLearningConfig, run_qlearning
from ergohandover.search.record import Budget
from ergohandover.search.rollouts import (
    random_policy,
    roll_out,
    step_limit,
    table_policy,
)
from ergohandover.search.statistics import (
    best_so_far,
    bootstrap_band,
    censored_median,
    cliffs_delta,
    wilson,
)
from ergohandover.search.targets import evaluations_to_target, target_cells
from ergohandover.search.walks import WalkConfig, run_randomwalk
from ergohandover.study.config import StudyConfig
from ergohandover.study.engines import Engine
from ergohandover.study.learning.config import StepBudget
from ergohandover.study.learning.runs import RunJob, run_job, run_seed, run_table
from ergohandover.study.learning.summary import comparisons, summary
from ergohandover.study.registry import part

ROOT = Path(__file__).resolve().parents[1]


def test_the_random_walk_is_deterministic_for_a_seed_and_moves_one_cell_a_step():
    a, b, c = (run_randomwalk(bowl_env(episode_end="none"), Budget(steps=20_000), s)
               for s in (4, 4, 5))
    pd.testing.assert_frame_equal(a.trace.drop(columns="time_s"),
                                  b.trace.drop(columns="time_s"))
    assert a.best_cells == b.best_cells and a.steps == 20_000
    assert not a.trace.drop(columns="time_s").equals(c.trace.drop(columns="time_s"))
    # Episodes are cut every 10,000 steps (the registered truncation) and restarted.
    assert a.best_score == 5 and a.info["episodes"] == 3


def test_a_random_walk_restarts_every_episode_like_the_learner():
    env = bowl_env(episode_end="none")
    walk = run_randomwalk(env, Budget(steps=1_000), 0, WalkConfig(episode_steps=10))
    learner = run_qlearning(env, Budget(steps=1_000), 0, QLearningConfig(episode_steps=10))
    assert walk.info["episodes"] == learner.info["episodes"] == 101


def test_the_lexicographic_objective_ranks_by_each_score_in_turn():
    landscape = bowl_landscape()
    feasible = landscape.feasible
    paper = landscape.arrays["paper_postural"].astype(float)
    cells = np.arange(343)
    landscape.arrays["reba_ab"] = np.where(feasible, cells % 24 + 1, -1).astype(np.int8)
    landscape.arrays["rula"] = np.where(feasible, cells % 7 + 1, -1).astype(np.int8)
    trunk = ((cells % 11) - 5) * 8.3  # degrees, both signs
    landscape.arrays["trunk_flexion"] = trunk.astype(np.float32)
    lex = objective_values(landscape, LEXICOGRAPHIC)
    key = list(zip(paper[feasible], landscape.arrays["reba_ab"][feasible],
                   landscape.arrays["rula"][feasible], np.rint(np.abs(trunk[feasible])),
                   strict=True))
    order = np.argsort(lex[feasible], kind="stable")
    assert [key[i] for i in order] == sorted(key)
    assert np.isinf(lex[~feasible]).all()
    assert LandscapeScores(landscape, LEXICOGRAPHIC).score(flat(CENTRE)) == lex[flat(CENTRE)]


def test_the_vectorised_reward_is_the_envs_reward_in_every_cell():
    env = bowl_env()
    values = objective_values(bowl_landscape(), "paper_postural")
    assert env.rewards_of(values).tolist() == [env.reward(c) for c in range(343)]


def two_minima_env() -> tuple[HandoverEnv, np.ndarray]:
    """The bowl with a second minimum off the midline (x index 5)."""
    landscape = bowl_landscape()
    off = flat((5, 3, 3))
    for name in ("paper_postural", "reba", "reba_ab", "rula"):
        landscape.arrays[name][off] = 5
    return HandoverEnv(LandscapeScores(landscape)), objective_values(landscape, "paper_postural")


def test_targets_are_the_minimum_or_the_rewards_best_cells():
    env, values = two_minima_env()
    minimum = target_cells(env, values, "minimum")
    reward = target_cells(env, values, "reward")
    assert sorted(minimum.cells) == [flat(CENTRE), flat((5, 3, 3))]
    assert list(reward.cells) == [flat(CENTRE)]  # the symmetry term prefers the midline
    assert minimum.fraction == 2 / 343 and reward.location == (0.0, 1.09, 0.39)


def test_evaluations_to_target_is_the_first_visit_of_a_target_cell():
    env, values = two_minima_env()
    reward = target_cells(env, values, "reward")
    result = run_randomwalk(env, Budget(steps=30_000), 1, WalkConfig(episode_steps=50))
    reached = evaluations_to_target(result, reward)
    assert reached == result.best_cells[flat(CENTRE)]
    assert evaluations_to_target(run_randomwalk(env, Budget(steps=1), 1), reward) is None


def test_a_learned_table_rolls_out_to_the_minimum_and_a_random_walk_mostly_does_not():
    env = bowl_env(episode_end="none")
    result = run_qlearning(env, Budget(steps=100_000), 0, QLearningConfig(episode_steps=200))
    mask = np.zeros(343, dtype=bool)
    mask[flat(CENTRE)] = True
    starts = np.random.default_rng(0).integers(343, size=50)
    limit = step_limit(env)
    assert limit == 18
    greedy = roll_out(env, table_policy(result.q_table, 343), mask, starts, limit,
                      np.random.default_rng(1))
    walk = roll_out(env, random_policy, mask, starts, limit, np.random.default_rng(1))
    distance = np.abs(np.array(np.unravel_index(starts, (7, 7, 7))).T - 3).sum(axis=1)
    assert greedy.reached.all()
    assert (greedy.steps == distance).all()  # the shortest way, from every start
    assert walk.fraction < 0.3


def test_wilson_intervals_are_the_textbook_values():
    assert wilson(5, 10) == pytest.approx((0.2366, 0.7634), abs=1e-4)
    assert wilson(0, 10) == pytest.approx((0.0, 0.2775), abs=1e-4)
    assert wilson(10, 10) == pytest.approx((0.7225, 1.0), abs=1e-4)
    assert wilson(0, 200)[0] == 0.0 and wilson(200, 200)[1] == 1.0  # exactly
    assert wilson(20, 20)[1] == 1.0  # statsmodels leaves 1 - 1e-16 here
    assert all(math.isnan(v) for v in wilson(0, 0))


def test_censored_runs_rank_last_and_are_never_dropped():
    learner = np.array([10.0, 20.0, 30.0, np.nan])
    walk = np.array([100.0, np.nan, np.nan, np.nan])
    assert censored_median(learner) == 25.0 and math.isnan(censored_median(walk))
    assert cliffs_delta(learner, walk) == pytest.approx((12 - 1) / 16 - 0)


def test_best_so_far_and_its_bootstrap_band():
    at = np.array([1, 5, 10, 100])
    best = best_so_far(np.array([2, 10]), np.array([7.0, 5.0]), at)
    assert best.tolist() == [math.inf, 7.0, 5.0, 5.0]
    samples = np.array([[1.0, 0.0], [0.0, 0.0], [1.0, 1.0]])
    mean, low, high = bootstrap_band(samples, np.random.default_rng(0))
    assert mean.tolist() == pytest.approx([2 / 3, 1 / 3])
    assert (low <= mean).all() and (mean <= high).all() and low[1] == 0.0


def test_run_r_of_a_target_has_one_seed_and_runs_differ():
    seeds = {run_seed(2024, t, r) for t in ("paper", "rula") for r in range(100)}
    assert len(seeds) == 200
    assert run_seed(2024, "paper", 3) == run_seed(2024, "paper", 3)


@pytest.fixture
def bowl_file():
    """The bowl's (evaluator, grid), its landscape in the cache."""
    return cached_bowl()


def job(bowl_file, agent: str, run: int, steps: int = 5_000, rollouts: int = 0,
        kind: str = "search") -> RunJob:
    evaluator, grid = bowl_file
    return RunJob("bowl", evaluator, grid, "paper_postural", "minimum", agent, "short", steps,
                  None, run, run_seed(7, "bowl", run), kind, rollouts=rollouts,
                  rollout_seed=3)


def test_a_study_run_is_deterministic_for_its_seed_and_reports_its_target(bowl_file):
    a, b = (run_job(job(bowl_file, "qlearning", 0, steps=60_000, rollouts=10, kind="full"))
            for _ in range(2))
    pd.testing.assert_frame_equal(a["trace"].drop(columns="time_s"),
                                  b["trace"].drop(columns="time_s"))
    row = a["row"]
    assert row["reached"] and row["target_score"] == 5 and row["best_score"] == 5
    assert (row["found_x"], row["found_y"], row["found_z"]) == (0.0, 1.09, 0.39)
    assert row["rollouts"] == 10 and row["rollout_limit"] == 18
    assert row["rollout_reached"] == 10 and 0 < row["rollout_mean_steps"] <= 9
    assert pd.Series(row).drop(["elapsed_s", "steps_per_s"]).equals(
        pd.Series(b["row"]).drop(["elapsed_s", "steps_per_s"]))


def test_the_summary_counts_successes_with_intervals_and_compares_run_for_run(bowl_file):
    budgets = [StepBudget("b20", 1.0, 20.0, 20), StepBudget("b60", 1.0, 60.0, 60)]
    done = [run_job(job(bowl_file, agent, run, steps=60)) for agent in ("qlearning",
            "randomwalk", "random-draws") for run in range(4)]
    runs = run_table(done, lambda agent: budgets)
    assert len(runs) == 3 * 4 * 2 and set(runs["budget"]) == {"b20", "b60"}
    traces = {tuple(d["trace"].drop(columns="time_s").itertuples(index=False)) for d in done}
    assert len(traces) == len(done)  # no two runs repeat each other
    short = runs[runs["budget"] == "b20"]
    assert (short["evaluations"] <= 20).all()
    assert (short["reached"] == (short["evaluations_to_target"] <= 20)).all()
    table = summary(runs, pd.DataFrame()).set_index(["agent", "budget"])
    for (agent, budget), cell in runs.groupby(["agent", "budget"]):
        k = int(cell["reached"].sum())
        assert table.loc[(agent, budget), "successes"] == k
        assert table.loc[(agent, budget), "n_runs"] == 4
        assert (table.loc[(agent, budget), "ci_low"],
                table.loc[(agent, budget), "ci_high"]) == wilson(k, 4)
    tests = comparisons(runs, ("qlearning",), 0.1, 0.05)
    assert list(tests["versus"]) == ["randomwalk", "random-draws"] * 2
    assert (tests["n"] == 4).all() and tests["p_wilcoxon"].between(0, 1).all()
    assert tests["verdict"].isin(["better", "worse", "equivalent within ±10 pp",
                                  "no conclusion"]).all()


QUICK = ROOT / "experiments" / "configs" / "quick.json"


@pytest.mark.smoke
@pytest.mark.slow
def test_the_quick_learning_part_runs_paired_and_reads_every_budget_from_one_run(tmp_path):
    config = StudyConfig.load(QUICK, (
        'learning.targets=[{"name": "paper"}, {"name": "paper-reward", "goal": "reward"}]',
        'learning.agents=["qlearning", "dqn", "randomwalk", "random-draws", "hillclimb"]',
        "learning.runs=4", "learning.dqn_runs=2", "learning.full_runs=2",
        "landscape.variants.step=0.08"))
    assert part("learning").run(config, tmp_path, Engine("local", 2))
    folder = tmp_path / "learning"
    read = lambda name: pd.read_csv(folder / f"{name}.csv")  # noqa: E731
    runs, full, summary_, versus = (read(n) for n in ("runs", "full_runs", "summary",
                                                      "comparisons"))
    budgets = config.learning.step_budgets()
    cheap = runs[runs["agent"] != "dqn"]
    assert len(cheap) == 2 * 4 * 4 * len(budgets)  # targets x agents x runs x budgets
    dqn = runs[runs["agent"] == "dqn"]
    assert set(dqn["target"]) == {"paper"} and set(dqn["mapping"]) == {315.0}
    assert (runs.groupby(["target", "run"])["seed"].nunique() == 1).all()  # paired
    # Every budget of a cheap agent's run is read from one run at the largest budget.
    assert set(cheap["run_budget"]) == {budgets[-1].name}
    assert set(runs["stopped_by"]) <= {"stop_score", "step_cap"}
    # A full run repeats its search run up to the target (the same seed, the same walk).
    searched = cheap.set_index(["target", "agent", "budget", "run"])
    for row in full.itertuples():
        first = searched.loc[(row.target, row.agent, row.budget, row.run)]
        assert row.reached == first["reached"]
        if row.reached:
            assert row.evaluations_to_target == first["evaluations_to_target"]
    assert {"rollout_rate", "mapping", "cap_min"} <= set(summary_.columns)
    assert set(versus["agent"]) == {"qlearning", "dqn"}
    assert (versus["p_wilcoxon_holm"] >= versus["p_wilcoxon"]).all()
    assert (folder / "power.csv").is_file() and (folder / "found.csv").is_file()
