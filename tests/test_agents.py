"""Agents: Q-learning (determinism, does it learn, the adaptive temperature), the search
baselines, the exhaustive ground truth, budgets, result files and a short DQN run."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest
from synthetic import CENTRE, bowl_env, bowl_landscape, flat

from ergohandover.envs import HandoverEnv, LandscapeScores
from ergohandover.landscape.stats import exhaustive
from ergohandover.search.qlearning import QLearningConfig, adapt_temperature, run_qlearning
from ergohandover.search.record import TRACE_COLUMNS, Budget, write_record
from ergohandover.search.walks import run_hillclimb, run_random_draws, run_randomwalk

ADAPTIVE = QLearningConfig(temperature="adaptive")


def greedy_reaches(env, q_table, start: int, target: int, limit: int = 20) -> bool:
    """Does following argmax Q from ``start`` reach ``target`` within ``limit`` moves?"""
    rows = dict(zip(q_table[0].tolist(), q_table[1], strict=True))
    cell = start
    for _ in range(limit):
        if cell == target:
            return True
        if cell not in rows:
            return False
        cell = env.transition(cell, int(np.argmax(rows[cell])))[0]
    return cell == target


def test_step_capped_qlearning_is_deterministic():
    runs = [run_qlearning(bowl_env(), Budget(steps=30_000), seed, ADAPTIVE)
            for seed in (7, 7, 8)]
    a, b, c = runs
    pd.testing.assert_frame_equal(a.trace.drop(columns="time_s"),
                                  b.trace.drop(columns="time_s"))
    np.testing.assert_array_equal(a.q_table[0], b.q_table[0])
    np.testing.assert_array_equal(a.q_table[1], b.q_table[1])
    assert a.best_cells == b.best_cells and a.info == b.info and a.steps == b.steps == 30_000
    assert not np.array_equal(a.q_table[1], c.q_table[1])  # the seed matters


def test_qlearning_learns_the_bowls_minimum():
    env = bowl_env(episode_end="none")
    result = run_qlearning(env, Budget(steps=100_000), 0, QLearningConfig(episode_steps=200))
    assert result.best_score == 5 and list(result.best_cells) == [flat(CENTRE)]
    assert result.first_reached[1] < 5_000
    feasible = [c for c in range(343) if env.scores.score(c) < math.inf]
    # The greedy policy of the learned table walks from every feasible cell to the minimum.
    assert all(greedy_reaches(env, result.q_table, c, flat(CENTRE)) for c in feasible)
    assert result.info["visited_states"] == 343


def test_with_the_papers_episode_end_the_learned_policy_avoids_the_target():
    # Rewards are positive, so ending the episode forfeits the rest: a documented property of
    # the paper's reward with its episode end, not of our code.
    env = bowl_env(target=5)
    result = run_qlearning(env, Budget(steps=100_000), 0, QLearningConfig(episode_steps=200))
    assert result.best_score == 5  # it is found (and the run remembers it) ...
    feasible = [c for c in range(343) if env.scores.score(c) < math.inf]
    reach = sum(greedy_reaches(env, result.q_table, c, flat(CENTRE)) for c in feasible)
    assert reach < len(feasible) / 10  # ... but the greedy policy walks around it


@pytest.mark.parametrize(("tau", "old", "new", "expected"), [
    (0.7, 6, 7, 0.8),             # worse: up
    (0.7, 6, math.inf, 0.8),      # an infeasible cell is worse than any score
    (0.7, 5, 4, 0.6),             # better and below the threshold 5: down
    (0.7, 6, 5, 0.7),             # better but not below 5: unchanged
    (0.7, 5, 5, 0.7),             # same: unchanged
    (2.0, 6, 7, 2.0),             # bounded above
    (0.1, 5, 4, 0.1),             # and below
    (0.7, math.inf, 4, 0.6),
])
def test_the_adaptive_temperature_follows_the_papers_text(tau, old, new, expected):
    assert adapt_temperature(tau, old, new, ADAPTIVE) == pytest.approx(expected)


def test_the_adaptive_temperature_moves_and_stays_bounded():
    fixed = run_qlearning(bowl_env(), Budget(steps=5_000), 0)
    adaptive = run_qlearning(bowl_env(), Budget(steps=5_000), 0, ADAPTIVE)
    assert fixed.info["final_temperature"] == 0.7
    # The bowl's minimum is 5, so the temperature never falls: it climbs to its bound.
    assert adaptive.info["final_temperature"] == 2.0


@pytest.mark.parametrize("agent", [run_random_draws, run_hillclimb])
def test_search_baselines_find_the_minimum_deterministically(agent):
    a, b = (agent(bowl_env(), Budget(steps=3_000), 3) for _ in range(2))
    assert a.best_score == 5 and list(a.best_cells) == [flat(CENTRE)]
    assert a.steps == 3_000 and a.stopped_by == "step_cap"
    pd.testing.assert_frame_equal(a.trace.drop(columns="time_s"),
                                  b.trace.drop(columns="time_s"))
    assert a.first_reached[1] < 1_500


def test_hillclimbing_climbs_the_reward_from_a_fixed_start():
    env = bowl_env(start=(0, 3, 3))  # a straight line of improving scores to the centre
    result = run_hillclimb(env, Budget(steps=18), 0)
    # Two moves (six looks each), then the centre is the first look (+x) of the third.
    assert result.best_score == 5 and result.first_reached[1] == 2 * 6 + 1


def test_a_time_cap_stops_the_run_and_not_before_it():
    result = run_qlearning(bowl_env(), Budget(seconds=0.3), 0)
    # Only what the clock cannot make flaky: the cap ended the run, and not early.
    assert result.stopped_by == "time_cap" and result.elapsed_s >= 0.3
    assert result.trace["time_s"].iloc[-1] == pytest.approx(result.elapsed_s, abs=1e-6)


@pytest.mark.parametrize("agent", [run_qlearning, run_randomwalk, run_random_draws, run_hillclimb])
def test_stop_score_ends_the_run_when_reached(agent):
    result = agent(bowl_env(), Budget(steps=100_000, stop_score=5), 0)
    assert result.stopped_by == "stop_score" and result.steps == result.first_reached[1]
    assert result.best_score <= 5


@pytest.mark.parametrize("agent", [run_qlearning, run_randomwalk, run_random_draws, run_hillclimb])
def test_without_a_stop_score_the_run_spends_its_whole_budget(agent):
    result = agent(bowl_env(), Budget(steps=3_000), 0)
    assert result.stopped_by == "step_cap" and result.steps == 3_000


@pytest.mark.parametrize(("kwargs", "message"), [
    ({}, "needs a time cap, a step cap or an evaluation cap"),
    ({"seconds": 0.0}, "seconds = 0.0 is outside the valid range"),
    ({"steps": 0}, "steps = 0 is outside the valid range"),
    ({"evaluations": 0}, "evaluations = 0 is outside the valid range"),
    ({"steps": 5, "evaluations": 5}, "counts steps or evaluations, not both"),
])
def test_bad_budgets_are_rejected(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Budget(**kwargs)


def test_bad_qlearning_settings_are_rejected():
    with pytest.raises(ValueError, match="temperature = 'cold' is not allowed"):
        QLearningConfig(temperature="cold")
    with pytest.raises(ValueError, match="alpha = 0 is outside the valid range"):
        QLearningConfig(alpha=0)


def test_exhaustive_reads_the_ground_truth():
    landscape = bowl_landscape()
    truth = exhaustive(landscape)
    assert truth.score == 5 and truth.cells.tolist() == [flat(CENTRE)]
    assert truth.location == pytest.approx((0.0, 1.09, 0.39))
    assert truth.fraction == pytest.approx(1 / 342)


def test_results_are_written_with_the_most_symmetric_best_location_first(tmp_path):
    env = bowl_env()
    result = run_qlearning(env, Budget(steps=2_000), 0)
    result.best_cells = {flat((4, 3, 3)): 5, flat(CENTRE): 9}  # two locations at the best
    paths = write_record(result, env.location, tmp_path / "run", {"agent": "qlearning"},
                         {"run": 0})
    assert sorted(p.name for p in paths) == ["best_locations.csv", "manifest.json",
                                            "q_table.npz", "trace.csv"]
    trace = pd.read_csv(tmp_path / "run" / "trace.csv")
    assert tuple(trace.columns) == TRACE_COLUMNS and trace["step"].iloc[-1] == 2_000
    assert trace["best_score"].is_monotonic_decreasing
    best = pd.read_csv(tmp_path / "run" / "best_locations.csv")
    assert best[["x", "y", "z"]].iloc[0].tolist() == pytest.approx([0.0, 1.09, 0.39])
    assert best["first_step"].tolist() == [9, 5]
    with np.load(tmp_path / "run" / "q_table.npz") as q:
        np.testing.assert_array_equal(q["states"], result.q_table[0])
        np.testing.assert_array_equal(q["q"], result.q_table[1])
    manifest = json.loads((tmp_path / "run" / "manifest.json").read_text())
    assert manifest["summary"]["best_score"] == 5 and manifest["seeds"] == {"run": 0}


@pytest.mark.slow
def test_a_short_dqn_run_keeps_its_caps_and_its_best():
    from ergohandover.search.dqn import DQNConfig, run_dqn

    config = DQNConfig(learning_starts=100, buffer_size=1_000, exploration_steps=300)
    runs = [run_dqn(bowl_env(observation="position"), Budget(steps=600), 1, config)
            for _ in range(2)]
    a, b = runs
    assert a.steps == 600 and a.stopped_by == "step_cap" and a.model is not None
    assert a.best_score == 5  # 600 steps on 343 cells, mostly exploring
    pd.testing.assert_frame_equal(a.trace.drop(columns="time_s"),
                                  b.trace.drop(columns="time_s"))
    with pytest.raises(ValueError, match="observation = 'position'"):
        run_dqn(bowl_env(), Budget(steps=10), 0)


def test_infeasible_cells_are_never_best_locations():
    landscape = bowl_landscape(infeasible=[(i, j, k) for i in range(7) for j in range(7)
                                           for k in range(7) if (i, j, k) != CENTRE])
    env = HandoverEnv(LandscapeScores(landscape), start=(0, 0, 0))
    result = run_hillclimb(env, Budget(steps=6), 0)  # every move from the corner is infeasible
    assert result.best_score == math.inf and result.best_cells == {}
    assert result.trace["best_score"].tolist() == [math.inf]


def test_a_q_table_reused_from_the_previous_run_starts_at_zero():
    """Runs in one process share a spare zeroed table: a run after another is the same run."""
    from ergohandover.search import qlearning

    qlearning._SPARE.clear()
    first = qlearning.run_qlearning(bowl_env(), Budget(steps=5000), 3)
    assert len(qlearning._SPARE) == 1  # its table, zeroed again, is kept
    second = qlearning.run_qlearning(bowl_env(), Budget(steps=5000), 3)
    for a, b in zip(first.q_table, second.q_table, strict=True):
        assert np.array_equal(a, b)
    assert first.trace.drop(columns="time_s").equals(second.trace.drop(columns="time_s"))
    spare = np.frombuffer(qlearning._SPARE[6 * 343], dtype=np.float64)
    assert not spare.any()
