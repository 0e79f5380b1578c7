"""What lets the learning study run each agent once per target and run and still report every
budget: a run with a smaller step cap is the first part of the run with a larger one, for every
agent but DQN, and stopping at the first target cell changes nothing a budget reports. Then the
paired statistics: Holm and the equivalence test against statsmodels and by hand, the verdicts,
and the power the study states."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats
from statsmodels.stats.contingency_tables import mcnemar
from statsmodels.stats.multitest import multipletests
from statsmodels.stats.proportion import binom_test

from ergohandover.envs import LandscapeScores
from ergohandover.landscape.cache import Landscape, landscape_key, landscape_path
from ergohandover.landscape.grid import Grid
from ergohandover.search import Budget, make
from ergohandover.search import run as run_search
from ergohandover.search.statistics import (
    equivalence_p,
    holm,
    mcnemar_power,
    paired_comparison,
    tost_power,
    verdict,
)
from ergohandover.study.config import StudyConfig
from ergohandover.study.learning.config import StepBudget
from ergohandover.study.learning.part import CHEAP, cheap, plan_jobs
from ergohandover.study.learning.runs import RunJob, budget_rows, run_job, run_seed
from ergohandover.study.learning.summary import comparisons
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary

ROOT = Path(__file__).resolve().parents[1]
RUGGED = Boundary((-0.21, 0.21), (0.90, 1.32), (0.30, 0.72))  # 15 x 15 x 15 cells every 3 cm


def rugged_landscape() -> Landscape:
    """15³ cells of random scores 5-9 (seeded), 4 at three cells, a few infeasible: a target
    that some runs find within a few thousand evaluations and some do not."""
    grid = Grid(RUGGED, 0.03)
    rng = np.random.default_rng(0)
    score = rng.integers(5, 10, size=grid.size).astype(np.int8)
    score[[1_000, 2_000, 3_000]] = 4
    flags = np.where(rng.random(grid.size) < 0.02, 4, 0).astype(np.uint8)
    flags[[1_000, 2_000, 3_000]] = 0
    arrays = {"flags": flags}
    for name in ("paper_postural", "reba", "reba_ab", "rula"):
        arrays[name] = np.where(flags == 0, score, -1).astype(np.int8)
    return Landscape(grid, "rugged", arrays, {})


class RecordingScores(LandscapeScores):
    """A landscape's scores that remember every cell they were asked for, in order."""

    def __init__(self, landscape: Landscape):
        super().__init__(landscape)
        self.asked: list[int] = []

    def score(self, flat: int) -> float:
        self.asked.append(flat)
        return super().score(flat)


def recorded_run(name: str, steps: int, seed: int = 11) -> tuple[list[int], object]:
    scores = RecordingScores(rugged_landscape())
    agent = make(name, scores.grid, seed, episode_end="none", episode_steps=500)
    return scores.asked, run_search(agent, scores, Budget(steps=steps))


@pytest.mark.parametrize("name", CHEAP)
def test_a_smaller_step_cap_is_the_first_part_of_a_larger_one(name):
    # Caps that are not multiples of the agents' block of 4,096 random numbers.
    short, short_run = recorded_run(name, 5_003)
    long, long_run = recorded_run(name, 20_011)
    assert len(short) < len(long) and long[:len(short)] == short
    trace = long_run.trace[long_run.trace["step"] <= short_run.steps].drop(columns="time_s")
    shown = short_run.trace.drop(columns="time_s").iloc[:len(trace)]
    pd.testing.assert_frame_equal(shown.reset_index(drop=True), trace.reset_index(drop=True))
    if short_run.best_score == long_run.best_score:
        assert short_run.best_cells == {c: s for c, s in long_run.best_cells.items()
                                        if s <= short_run.steps}


@pytest.fixture
def rugged_file():
    """The rugged landscape in the test session's cache, for the study's jobs."""
    landscape, evaluator = rugged_landscape(), Evaluator()
    key = landscape_key(evaluator, landscape.grid)
    Landscape(landscape.grid, key, landscape.arrays, landscape.meta).save(landscape_path(key))
    return evaluator, landscape.grid


@pytest.mark.parametrize("name", CHEAP)
def test_one_run_stopped_at_the_target_reports_every_budget_as_runs_capped_there(name,
                                                                                  rugged_file):
    evaluator, grid = rugged_file
    budgets = [StepBudget(f"b{steps}", 1.0, steps, steps) for steps in (300, 1_500, 6_000)]
    for run in range(4):
        seed = run_seed(3, "rugged", run)
        search = run_job(RunJob("rugged", evaluator, grid, "paper_postural", "minimum", name,
                                "b6000", 6_000, None, run, seed, "search", oracle_stop=True))
        read = budget_rows(search["row"], search["trace"], budgets)
        for budget, row in zip(budgets, read, strict=True):
            capped = run_job(RunJob("rugged", evaluator, grid, "paper_postural", "minimum",
                                    name, budget.name, budget.steps, None, run, seed, "full"))
            for key in ("reached", "best_score", "evaluations_to_target"):
                assert row[key] == capped["row"][key] or (
                    math.isnan(row[key]) and math.isnan(capped["row"][key])), (budget, key)
        assert search["row"]["evaluations"] <= 6_000


def test_run_r_has_one_seed_for_every_agent_and_budget():
    config = StudyConfig.load(ROOT / "experiments" / "configs" / "quick.json")
    jobs = plan_jobs(config)
    seeds = pd.DataFrame([(j.target, j.agent, j.budget, j.run, j.seed) for j in jobs],
                         columns=["target", "agent", "budget", "run", "seed"])
    per_run = seeds.groupby(["target", "run"])["seed"].nunique()
    assert (per_run == 1).all()  # every agent, every kind of run
    assert seeds.drop_duplicates(["target", "run"])["seed"].is_unique
    assert set(seeds["agent"]) == set(config.learning.agents)
    dqn = seeds[seeds["agent"] == "dqn"]
    assert set(dqn["target"]) == {"paper"} and set(dqn["budget"]) == {"quick-long"}
    largest = config.learning.step_budgets()[-1].name
    searches = [j for j in jobs if j.kind == "search" and cheap(j.agent)]
    assert {j.budget for j in searches} == {largest} and all(j.oracle_stop for j in searches)


def test_holm_is_statsmodels_and_the_textbook_step_down():
    p = np.array([0.01, 0.04, 0.03, 0.005])
    assert holm(p) == pytest.approx(multipletests(p, method="holm")[1])
    # By hand: sorted 0.005, 0.01, 0.03, 0.04 times 4, 3, 2, 1, kept non-decreasing.
    assert holm(p) == pytest.approx([0.03, 0.06, 0.06, 0.02])


def test_the_tost_is_two_exact_binomial_tests_on_the_discordant_runs():
    # 100 runs, 2 where only a succeeded and 1 where only b did, margin 10 points.
    assert equivalence_p(2, 1, 100, 0.1) == pytest.approx(
        max(binom_test(2, 100, 0.1, "smaller"), binom_test(1, 100, 0.1, "smaller")))
    # By hand: every pair agrees, so p = P(Binomial(100, 0.1) = 0) = 0.9^100.
    assert equivalence_p(0, 0, 100, 0.1) == pytest.approx(0.9 ** 100)
    assert equivalence_p(0, 0, 20, 0.1) == pytest.approx(0.9 ** 20)  # 0.12: 20 runs prove nothing


def test_a_paired_comparison_ranks_censored_runs_last_and_matches_the_libraries():
    a = np.array([10.0, 20.0, 30.0, np.nan, 5.0, np.nan])
    b = np.array([100.0, np.nan, 25.0, np.nan, 50.0, 40.0])
    test = paired_comparison(a, b, 1_000, 0.1)
    assert test["n"] == 6
    # Pairs that differ: -90, -981 (b censored at 1,001), +5, -45, +961 (a censored).
    diff = np.array([-90, -981, 5, -45, 961])
    ranks = np.array([3, 5, 1, 2, 4])
    assert test["rank_biserial"] == pytest.approx((ranks[diff < 0].sum()
                                                   - ranks[diff > 0].sum()) / ranks.sum())
    assert test["p_wilcoxon"] == pytest.approx(stats.wilcoxon(diff).pvalue)
    # Success: both in 3 runs, only a in 1, only b in 1, neither in 1.
    assert test["p_mcnemar"] == pytest.approx(mcnemar([[3, 1], [1, 1]], exact=True).pvalue)
    assert test["p_tost"] == pytest.approx(equivalence_p(1, 1, 6, 0.1))
    same = paired_comparison(np.full(4, np.nan), np.full(4, np.nan), 10, 0.1)
    assert same["p_wilcoxon"] == 1.0 and same["rank_biserial"] == 0.0


@pytest.mark.parametrize(("p_diff", "effect", "p_equiv", "expected"), [
    (0.01, 0.4, 0.01, "better"),      # a difference wins over equivalence
    (0.01, -0.4, 0.5, "worse"),
    (0.2, 0.1, 0.01, "equivalent within ±10 pp"),
    (0.2, 0.1, 0.2, "no conclusion"),
    (0.05, 0.9, 0.05, "no conclusion"),  # at alpha exactly: not below it
])
def test_the_verdict_follows_the_corrected_tests(p_diff, effect, p_equiv, expected):
    assert verdict(p_diff, effect, p_equiv, 0.1, 0.05) == expected


def synthetic_runs() -> pd.DataFrame:
    """Two budgets of 100 paired runs: at the first the learner is sooner in every run; at the
    second every agent succeeds at once in every run."""
    rows = []
    for budget, steps in (("short", 1_000), ("long", 2_000)):
        for run in range(100):
            for agent, first in (("qlearning", 10 + run), ("randomwalk", 500 + run),
                                 ("random-draws", 11 + run)):
                value = float(first) if budget == "short" else 0.0
                rows.append({"target": "t", "budget": budget, "mapping": 315.0,
                             "cap_min": 1.0, "steps": steps, "agent": agent, "run": run,
                             "evaluations_to_target": value, "evaluations": value})
    return pd.DataFrame(rows)


@pytest.mark.slow
def test_the_comparisons_correct_over_the_whole_family_and_give_verdicts():
    table = comparisons(synthetic_runs(), ("qlearning",), 0.1, 0.05)
    assert len(table) == 4 and (table["n"] == 100).all()
    for test in ("p_wilcoxon", "p_mcnemar", "p_tost"):
        assert table[f"{test}_holm"].to_numpy() == pytest.approx(
            multipletests(table[test], method="holm")[1])
    at = table.set_index(["budget", "versus"])
    assert at.loc[("short", "randomwalk"), "verdict"] == "better"
    assert at.loc[("short", "randomwalk"), "rank_biserial"] == 1.0
    assert at.loc[("short", "random-draws"), "verdict"] == "better"  # sooner by 1 in every run
    # Everyone at once in every run: no difference, success rates equal in every pair.
    assert at.loc[("long", "randomwalk"), "p_wilcoxon"] == 1.0
    assert at.loc[("long", "randomwalk"), "p_tost"] == pytest.approx(0.9 ** 100)
    assert at.loc[("long", "randomwalk"), "verdict"] == "equivalent within ±10 pp"


def test_the_stated_power_is_what_the_tests_do():
    # Every run concordant: the TOST rejects exactly when 0.9^n is below alpha.
    assert tost_power(100, 0.0, 0.1, 0.05) == 1.0 and tost_power(20, 0.0, 0.1, 0.05) == 0.0
    # McNemar's exact test against a simulation of paired runs (seeded).
    rng = np.random.default_rng(5)
    draws = rng.multinomial(30, [0.3, 0.05, 0.65], size=4_000)
    rejected = np.mean([mcnemar([[0, b], [c, 0]], exact=True).pvalue < 0.05
                        for b, c, _ in draws])
    assert mcnemar_power(30, 0.3, 0.05, 0.05) == pytest.approx(rejected, abs=0.025)



def test_a_job_uses_the_target_its_parent_prepared(rugged_file, monkeypatch):
    """The parent computes each target once before the pool forks; a job then reads no
    landscape of its own."""
    from ergohandover.study.learning import runs as learning_runs

    evaluator, grid = rugged_file
    landscape = Landscape(grid, landscape_key(evaluator, grid), rugged_landscape().arrays, {})
    monkeypatch.setattr(learning_runs, "_TARGETS", {})
    prepared = learning_runs.prepare_target(landscape, "paper_postural", "minimum")

    def no_reading(*args, **kwargs):
        raise AssertionError("a job read a landscape its parent had prepared")

    monkeypatch.setattr(learning_runs, "landscape_of", no_reading)
    assert learning_runs.target_of(evaluator, grid, "paper_postural", "minimum") is prepared
    row = run_job(RunJob("rugged", evaluator, grid, "paper_postural", "minimum", "qlearning",
                         "b300", 300, None, 0, 1, "search", oracle_stop=True))["row"]
    assert row["target_score"] == 4
