"""The learning study's parts: the random walk, the lexicographic objective, targets, greedy
rollouts, the statistics and the study's runs (seeds of their own, determinism)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats
from synthetic import CENTRE, bowl_env, bowl_landscape, cached_bowl, flat

from ergohandover.envs import HandoverEnv, LandscapeScores
from ergohandover.envs.scores import LEXICOGRAPHIC, objective_values
from ergohandover.learning.qlearning import QLearningConfig, run_qlearning
from ergohandover.learning.rollouts import (
    random_policy,
    roll_out,
    step_limit,
    table_policy,
)
from ergohandover.learning.search import run_randomwalk
from ergohandover.learning.statistics import (
    best_so_far,
    bootstrap_band,
    censored_median,
    cliffs_delta,
    compare,
    wilson,
)
from ergohandover.learning.targets import evaluations_to_target, target_cells
from ergohandover.learning.trace import Budget
from ergohandover.study.learning_runs import RunJob, run_job, run_seed
from ergohandover.study.learning_summary import comparisons, summary


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
    walk = run_randomwalk(env, Budget(steps=1_000), 0, episode_steps=10)
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
    result = run_randomwalk(env, Budget(steps=30_000), 1, episode_steps=50)
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


def test_censored_runs_rank_last_and_are_never_dropped():
    learner = np.array([10.0, 20.0, 30.0, np.nan])
    walk = np.array([100.0, np.nan, np.nan, np.nan])
    assert censored_median(learner) == 25.0 and math.isnan(censored_median(walk))
    assert cliffs_delta(learner, walk) == pytest.approx((12 - 1) / 16 - 0)
    test = compare(learner, walk)
    ranks_p = stats.mannwhitneyu([10, 20, 30, np.inf], [100, np.inf, np.inf, np.inf]).pvalue
    assert test["p_mannwhitney"] == pytest.approx(ranks_p)
    assert test["p_fisher"] == pytest.approx(stats.fisher_exact([[3, 1], [1, 3]]).pvalue)
    assert compare(np.full(3, np.nan), np.full(3, np.nan))["p_mannwhitney"] == 1.0


def test_best_so_far_and_its_bootstrap_band():
    at = np.array([1, 5, 10, 100])
    best = best_so_far(np.array([2, 10]), np.array([7.0, 5.0]), at)
    assert best.tolist() == [math.inf, 7.0, 5.0, 5.0]
    samples = np.array([[1.0, 0.0], [0.0, 0.0], [1.0, 1.0]])
    mean, low, high = bootstrap_band(samples, np.random.default_rng(0))
    assert mean.tolist() == pytest.approx([2 / 3, 1 / 3])
    assert (low <= mean).all() and (mean <= high).all() and low[1] == 0.0


def test_every_run_has_a_seed_of_its_own():
    seeds = {run_seed(2024, t, a, b, r) for t in ("paper", "rula") for a in ("qlearning", "dqn")
             for b in ("paper-2min", "paper-5min") for r in range(10)}
    assert len(seeds) == 80
    assert run_seed(2024, "paper", "dqn", "paper-2min", 3) == run_seed(2024, "paper", "dqn",
                                                                      "paper-2min", 3)


@pytest.fixture
def bowl_file():
    """The bowl's (evaluator, grid), its landscape in the cache."""
    return cached_bowl()


def job(bowl_file, agent: str, run: int, steps: int = 5_000, rollouts: int = 0) -> RunJob:
    evaluator, grid = bowl_file
    return RunJob("bowl", evaluator, grid, "paper_postural", "minimum", agent, "short", steps,
                  None, run, run_seed(7, "bowl", agent, "short", run), rollouts=rollouts,
                  rollout_seed=3)


def test_a_study_run_is_deterministic_for_its_seed_and_reports_its_target(bowl_file):
    a, b = (run_job(job(bowl_file, "qlearning", 0, steps=60_000, rollouts=10))
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


def test_the_summary_counts_successes_with_intervals_and_compares_with_the_walk(bowl_file):
    done = [run_job(job(bowl_file, agent, run, steps=60)) for agent in ("qlearning",
            "randomwalk", "random") for run in range(4)]
    runs = pd.DataFrame([d["row"] for d in done])
    traces = {tuple(d["trace"].drop(columns="time_s").itertuples(index=False)) for d in done}
    assert len(traces) == len(done)  # no two runs repeat each other
    table = summary(runs).set_index("agent")
    for agent, cell in runs.groupby("agent"):
        k = int(cell["reached"].sum())
        assert table.loc[agent, "successes"] == k and table.loc[agent, "n_runs"] == 4
        assert (table.loc[agent, "ci_low"], table.loc[agent, "ci_high"]) == wilson(k, 4)
    tests = comparisons(runs, ("qlearning",))
    assert list(tests["versus"]) == ["randomwalk", "random"]
    assert tests["p_mannwhitney"].between(0, 1).all()
