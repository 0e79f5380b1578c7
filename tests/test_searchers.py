"""Ask/tell searchers: proposals inside the grid, determinism, replay, warm starts, infeasible
answers, finding a bowl's minimum far sooner than random, the env-driven agents measured in
evaluations, and the searchers as agents of ``train``."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from synthetic import bowl_landscape

from ergohandover.cli import main
from ergohandover.envs import ArrayScores, LandscapeScores
from ergohandover.envs.scores import objective_values
from ergohandover.errors import ConfigError
from ergohandover.landscape.grid import Grid
from ergohandover.search import SEARCHERS, Budget, make, replay, run
from ergohandover.search.prior import Prior
from ergohandover.twin.task import Boundary

N = 15
GRID = Grid(Boundary((0.0, 0.14), (1.0, 1.14), (0.3, 0.44)), 0.01)  # 15 x 15 x 15 cells
CENTRE = (9, 5, 7)  # off the grid's centre: no searcher starts on it
PRIOR = Prior((0.11, 1.07, 0.39), (0.02, 0.02, 0.02))  # cell (11, 7, 9): 3.5 cells off
OPTIMISERS = ("bo", "tpe", "cmaes", "pso")
WARM = ("prior", *OPTIMISERS)  # the searchers that take a prior
NAMES = ("random-order", *WARM)


def bowl_values(infeasible=lambda i, j, k: (i >= N - 3) & (j >= N - 3) & (k >= N - 3)):
    """5 + the rounded distance [cells] to ``CENTRE`` (a unique minimum 5), ``inf`` in an
    infeasible corner."""
    i, j, k = np.indices(GRID.shape).reshape(3, -1)
    d = np.sqrt((i - CENTRE[0]) ** 2 + (j - CENTRE[1]) ** 2 + (k - CENTRE[2]) ** 2)
    return np.where(infeasible(i, j, k), np.inf, 5 + np.rint(d))


VALUES = bowl_values()


def searcher(name: str, seed: int = 0, prior: Prior | None = None):
    return make(name, GRID, seed, PRIOR if name == "prior" else prior)


def search(name: str, seed: int = 0, budget: int = 30, prior: Prior | None = None,
           values=VALUES, stop_at=None):
    return run(searcher(name, seed, prior), ArrayScores(GRID, values),
               Budget(evaluations=budget, stop_score=stop_at))


def test_every_searcher_is_registered():
    assert set(NAMES) <= set(SEARCHERS)


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.slow
def test_proposals_are_distinct_cells_inside_the_grid(name):
    record = search(name)
    assert all(0 <= c < GRID.size for c in record.cells)
    assert len(set(record.cells)) == len(record.cells) == record.steps == 30
    assert record.info["asks"] == 30  # never a known cell: every ask is a new handover
    assert record.unit == "evaluations" and record.stopped_by == "evaluation_cap"


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.slow
def test_a_seed_fixes_the_proposals(name):
    assert search(name, seed=4).cells == search(name, seed=4).cells
    assert search(name, seed=4).cells != search(name, seed=5).cells


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.slow
def test_replaying_a_history_reproduces_the_next_proposal(name):
    first = searcher(name, seed=2)
    record = run(first, ArrayScores(GRID, VALUES), Budget(evaluations=20))
    resumed = replay(searcher(name, seed=2), list(zip(record.cells, record.scores,
                                                       strict=True)))
    assert resumed.ask() == first.ask()


@pytest.mark.parametrize("name", WARM)
def test_with_a_prior_the_first_proposal_is_the_priors_cell(name):
    assert searcher(name, prior=PRIOR).ask() == GRID.nearest_cell(PRIOR.location)


@pytest.mark.parametrize("name", ["prior", "cmaes", "pso", "bo"])
def test_a_prior_beyond_the_grid_is_clamped_into_it(name):
    outside = Prior((0.5, 0.0, 0.41), (0.02, 0.02, 0.02))  # beyond +x and below -y
    cell = make(name, GRID, 0, outside).ask()
    assert np.unravel_index(cell, GRID.shape) == (N - 1, 0, 11)


def test_the_prior_searcher_needs_a_prior():
    with pytest.raises(ConfigError, match="searcher prior needs a worker's prior"):
        make("prior", GRID, 0)


def test_an_unknown_searcher_and_a_wrong_answer_are_refused():
    with pytest.raises(ConfigError, match="searcher = 'sarsa' is not allowed"):
        make("sarsa", GRID, 0)
    s = searcher("cmaes")
    asked = s.ask()
    assert s.ask() == asked  # asking again without an answer: the same cell
    with pytest.raises(ConfigError, match=f"told cell {asked + 1}, but it asked for cell {asked}"):
        s.tell(asked + 1, 5.0)


def evaluations_to_minimum(name: str, seed: int, budget: int) -> float:
    found = search(name, seed, budget, stop_at=5).reached_at(5)
    return math.inf if found is None else found


@pytest.mark.parametrize("name", OPTIMISERS)
@pytest.mark.slow
def test_optimisers_find_the_bowls_minimum_far_sooner_than_random(name):
    seeds = range(5)
    random = [evaluations_to_minimum("random-order", s, GRID.size) for s in seeds]
    found = [evaluations_to_minimum(name, s, 300) for s in seeds]
    # Random needs ~half the 3,348 feasible cells; these need tens (GP, CMA-ES) to about a
    # hundred (TPE, PSO) on this bowl.
    assert np.median(found) <= np.median(random) / 2, (found, random)


@pytest.mark.parametrize("name", WARM)
@pytest.mark.slow
def test_infeasible_answers_are_handled(name):
    # Half the grid infeasible and the prior's cell in it, so the first answer is infeasible
    # (the Optuna searchers have no objective value for it until a feasible answer comes).
    values = bowl_values(lambda i, j, k: i >= 8)
    inside = Prior((0.09, 1.07, 0.39), (0.02, 0.02, 0.02))  # cell (9, 7, 9)
    record = search(name, seed=1, budget=40, prior=inside, values=values)
    assert math.isinf(record.scores[0]) and record.info["asks"] == len(set(record.cells)) == 40
    assert math.isfinite(min(record.scores))  # it left the infeasible half


@pytest.mark.slow
def test_bo_learns_where_the_infeasible_region_is():
    values = bowl_values(lambda i, j, k: i >= 8)  # the minimum's cell (9, 5, 7) is infeasible
    record = search("bo", seed=0, budget=40, values=values)
    infeasible = sum(math.isinf(s) for s in record.scores[10:])  # after the 10 random starts
    assert infeasible <= 10  # the feasibility model steers it away (about half at random)


@pytest.mark.slow
def test_bo_proposes_what_optunas_own_path_proposes(monkeypatch):
    # GPSearcher skips the cost of Optuna's torch device mode; the proposals must not change.
    from ergohandover.search.optuna_searchers import GPSearcher, OptunaSearcher

    values = bowl_values(lambda i, j, k: i >= 8)
    fast = search("bo", seed=3, budget=18, prior=PRIOR, values=values)
    monkeypatch.setattr(GPSearcher, "_ask_trial", OptunaSearcher._ask_trial)
    plain = search("bo", seed=3, budget=18, prior=PRIOR, values=values)
    assert fast.cells == plain.cells and len(fast.cells) == 18


def test_bo_adds_known_answers_without_proposing_them():
    s = searcher("bo")
    known = [(c, float(VALUES[c])) for c in (0, 100, 2_000, 3_374)]  # 3,374: infeasible
    s.add_known(known)
    assert len(s.study.trials) == 4 and s.ask() not in {c for c, _ in known}


@pytest.mark.parametrize("agent", ["qlearning", "randomwalk"])
def test_env_agents_are_measured_in_distinct_evaluations(agent):
    landscape = bowl_landscape()
    values = objective_values(landscape, "paper_postural")
    scores = ArrayScores(landscape.grid, values)

    def measured(budget, stop_at=None):
        return run(make(agent, landscape.grid, 3), scores,
                   Budget(evaluations=budget, stop_score=stop_at))

    record = measured(40)
    assert len(record.cells) == len(set(record.cells)) == record.steps == 40
    assert record.scores == [values[c] for c in record.cells]
    assert record.info["asks"] > 40  # revisits were free
    assert measured(40).cells == record.cells
    stopped = measured(343, stop_at=5)
    assert stopped.scores[-1] == 5 and stopped.reached_at(5) == len(stopped.cells)
    assert stopped.stopped_by == "stop_score"


def test_scores_of_another_grid_are_refused():
    with pytest.raises(ConfigError, match="does not match the grid's"):
        ArrayScores(GRID, np.ones(10))


@pytest.mark.parametrize("name", ["pso", "cmaes", "tpe"])
def test_searchers_count_evaluations_and_refuse_steps(name):
    scores = LandscapeScores(bowl_landscape())
    result = run(make(name, scores.grid, 0), scores, Budget(evaluations=120))
    assert result.steps == 120 and result.stopped_by == "evaluation_cap"
    assert result.best_score == 5
    stopped = run(make(name, scores.grid, 0), scores, Budget(evaluations=343, stop_score=5))
    assert stopped.stopped_by == "stop_score" and stopped.steps == stopped.first_reached[1]
    with pytest.raises(ConfigError, match=f"searcher '{name}' counts evaluations, not steps"):
        run(make(name, scores.grid, 0), scores, Budget(steps=10))


@pytest.mark.parametrize("agent", ["bo", "pso"])
def test_train_runs_a_searcher(tmp_path, agent):
    bowl = bowl_landscape().save(tmp_path / "bowl.npz")
    out = tmp_path / agent
    assert main(["train", "--agent", agent, "--steps", "25", "--landscape", str(bowl),
                 "--output", str(out)]) == 0
    trace = pd.read_csv(out / "trace.csv")
    assert trace["step"].iloc[-1] == 25 and trace["best_score"].is_monotonic_decreasing


def test_train_refuses_the_prior_searcher_on_a_landscape_file(tmp_path, capsys):
    bowl = bowl_landscape().save(tmp_path / "bowl.npz")
    assert main(["train", "--agent", "prior", "--steps", "5", "--landscape", str(bowl)]) == 2
    assert "--agent prior cannot be used with --landscape" in capsys.readouterr().err
