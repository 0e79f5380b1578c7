"""The personalisation study's parts: the ask/tell loop, the population prior (fit, leave-one-out,
the shipped model equal to the committed population's fit), paired seeds and the summary's
success rates, intervals and censored medians."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from synthetic import BOWL, bowl_landscape, flat

from ergohandover.envs import ArrayScores
from ergohandover.envs.scores import Answer, objective_values
from ergohandover.errors import ConfigError
from ergohandover.landscape.grid import Grid
from ergohandover.search import AskTellSearcher, Budget, make, replay, run
from ergohandover.search.prior import PopulationPrior, Prior, shipped_prior
from ergohandover.study.personalise.sessions import (
    censored_at,
    leave_one_out_priors,
    run_seeds,
    success_curves,
    summary,
)

ROOT = Path(__file__).resolve().parents[1]
GRID = Grid(BOWL, 0.03)
VALUES = objective_values(bowl_landscape(), "paper_postural")  # minimum 5 at the centre


class Scripted(AskTellSearcher):
    """Proposes a fixed list of cells (repeats included)."""

    name = "scripted"

    def __init__(self, cells):
        super().__init__(GRID, 0)
        self.cells, self.told = list(cells), []

    def ask(self) -> int:
        return self.cells[len(self.told)]

    def tell(self, cell, answer) -> None:
        self.told.append((cell, answer))


SCORES = ArrayScores(GRID, VALUES)


def search(searcher, evaluations: int, stop_at: float | None = None):
    return run(searcher, SCORES, Budget(evaluations=evaluations, stop_score=stop_at))


def test_the_loop_counts_each_cell_once_and_stops_at_the_target():
    centre = flat((3, 3, 3))
    searcher = Scripted([0, 0, 1, centre, 2])
    record = search(searcher, 10, stop_at=5.0)
    # The repeat of cell 0 is answered from what is known and costs no evaluation.
    assert record.cells == [0, 1, centre] and record.info["asks"] == 4
    assert record.reached_at(5.0) == 3 and record.best == (centre, 5.0)
    assert record.stopped_by == "stop_score"
    assert searcher.told[1] == (0, Answer(float(VALUES[0])))


class WithPosture(ArrayScores):
    """A landscape whose every answer also carries the posture behind it."""

    def answer(self, flat):
        return Answer(self.score(flat), "posture", posture={"trunk_flexion": float(flat)})


def test_a_searcher_is_told_the_whole_answer_and_a_replay_tells_it_again():
    source = WithPosture(GRID, VALUES)
    searcher = make("random-order", GRID, 3)
    record = run(searcher, source, Budget(evaluations=4))
    heard = [searcher.heard[c] for c in record.cells]
    assert [a.posture["trunk_flexion"] for a in heard] == [float(c) for c in record.cells]
    assert [a.score for a in heard] == record.scores
    again = replay(make("random-order", GRID, 3), [(c, searcher.heard[c]) for c in record.cells])
    assert again.heard == searcher.heard
    # A bare score is an answer of a score alone; NaN is infeasible.
    scored = replay(make("random-order", GRID, 3), [(record.cells[0], float("nan"))])
    assert scored.heard[record.cells[0]] == Answer(math.inf)


def test_a_searcher_that_keeps_to_known_cells_ends():
    record = search(Scripted([0] * 1_000), 10)
    assert record.cells == [0] and record.stopped_by == "ask_cap"
    assert record.info["asks"] == 50 * 10  # the one guard: 50 reads per evaluation


def test_the_loop_keeps_to_its_budget_and_reports_infeasible_cells_as_inf():
    record = search(make("random-order", GRID, 3), 25)
    assert len(record.cells) == 25 == len(set(record.cells))
    infeasible = flat((6, 6, 6))
    answered = search(Scripted([infeasible]), 1)
    assert answered.scores == [math.inf] and answered.reached_at(99) is None
    assert answered.best is None
    with pytest.raises(ConfigError, match="evaluations = 0"):
        Budget(evaluations=0)


def test_random_order_is_seeded_and_replays_its_history():
    first = search(make("random-order", GRID, 7), 30)
    again = search(make("random-order", GRID, 7), 30)
    assert first.cells == again.cells
    resumed = replay(make("random-order", GRID, 7),
                     list(zip(first.cells[:12], first.scores[:12], strict=True)))
    assert resumed.ask() == first.cells[12]
    with pytest.raises(ConfigError, match="history trial 1"):
        replay(make("random-order", GRID, 8), [(first.cells[0], first.scores[0])])
    with pytest.raises(ConfigError, match="searcher = 'nope'"):
        make("nope", GRID, 0)


def synthetic_workers(n: int = 40, seed: int = 0) -> pd.DataFrame:
    """Workers whose optimum is exactly 0.3 + 0.4 * stature high and 2 cm further forward for
    men, with 1 cm of noise in height."""
    rng = np.random.default_rng(seed)
    stature = rng.uniform(1.5, 1.95, n)
    male = rng.random(n) < 0.5
    return pd.DataFrame({"worker": [f"w{i:03d}" for i in range(n)],
                         "sex": np.where(male, "male", "female"), "stature_m": stature,
                         "paper_postural_x": 0.0,
                         "paper_postural_y": 0.3 + 0.4 * stature + rng.normal(0, 0.01, n),
                         "paper_postural_z": 0.35 + 0.02 * male, "reference": 0})


def test_the_prior_recovers_a_linear_population_and_refuses_bad_workers():
    model = PopulationPrior.fit(synthetic_workers())
    tall_man = model.predict(1.90, "male")
    assert tall_man.location[1] == pytest.approx(0.3 + 0.4 * 1.90, abs=0.006)
    assert tall_man.location[2] == pytest.approx(0.37, abs=1e-9)
    # The height's residual spread is the noise's; an axis without spread gets the floor.
    assert 0.007 < model.residual_sd[1] < 0.013 and model.residual_sd[0] == model.floor_m
    with pytest.raises(ConfigError, match="sex = 'other'"):
        model.predict(1.7, "other")
    with pytest.raises(ConfigError, match=r"stature = 3\.1"):
        model.predict(3.1, "male")
    with pytest.raises(ConfigError, match="missing column"):
        PopulationPrior.fit(synthetic_workers().drop(columns="paper_postural_z"))
    with pytest.raises(ConfigError, match="prior sd"):
        Prior((0.0, 1.0, 0.4), (0.0, 0.01, 0.01))


def test_a_workers_leave_one_out_prior_ignores_its_own_optimum():
    workers = synthetic_workers()
    priors = leave_one_out_priors(workers, "paper_postural")
    moved = workers.copy()
    moved.loc[0, "paper_postural_y"] += 0.5  # the worker's own optimum, far off
    again = leave_one_out_priors(moved, "paper_postural")
    assert again["w000"] == priors["w000"]
    assert again["w001"] != priors["w001"]  # every other worker's prior sees it


def test_the_shipped_prior_is_the_fit_of_the_committed_population():
    workers = pd.read_csv(ROOT / "results" / "population" / "workers.csv")
    fitted = PopulationPrior.fit(workers)
    shipped = shipped_prior()
    assert np.allclose(shipped.coefficients, fitted.coefficients, atol=1e-12)
    assert np.allclose(shipped.residual_sd, fitted.residual_sd, atol=1e-12)
    document = json.loads((ROOT / "src" / "ergohandover" / "search" /
                           "population_prior.json").read_text())
    assert "results/population/workers.csv" in document["source"]
    # Taller workers are expected to take the box higher.
    assert shipped.predict(1.9, "male").location[1] > shipped.predict(1.6, "male").location[1]


def test_runs_are_paired_across_searchers_and_differ_across_workers():
    assert run_seeds(28, "w001", 10) == run_seeds(28, "w001", 10)
    assert len(set(run_seeds(28, "w001", 10))) == 10
    assert run_seeds(28, "w001", 3) == run_seeds(28, "w001", 10)[:3]
    assert set(run_seeds(28, "w001", 10)).isdisjoint(run_seeds(28, "w002", 10))


def test_the_median_at_a_budget_ranks_misses_last():
    assert censored_at(np.array([3.0, 5.0, np.nan]), 100) == 5.0
    assert math.isnan(censored_at(np.array([3.0, np.nan, np.nan]), 100))
    # At a budget of 4 the run that needed 5 is a miss too.
    assert math.isnan(censored_at(np.array([3.0, 5.0, 7.0]), 4))
    assert censored_at(np.array([3.0, 5.0, 70.0]), 10) == 5.0


def test_the_summary_reads_every_budget_from_the_runs():
    runs = pd.DataFrame({
        "worker": ["a"] * 4 + ["b"] * 4, "searcher": "s", "run": [0, 1, 2, 3] * 2,
        "evals_to_optimum": [5, 20, np.nan, 60, 8, 9, 200, np.nan],
        "evals_to_within_1": [1, 2, 3, 4, 1, 1, 1, 1]})
    table = summary(runs, {"s": [10, 50, 250]}, seed=0)
    optimum = table[table["target"] == "optimum"].set_index("budget")
    assert list(optimum["successes"]) == [3, 4, 6]
    assert list(optimum["success_rate"]) == [3 / 8, 4 / 8, 6 / 8]
    assert (optimum["ci_low"] <= optimum["success_rate"]).all()
    assert (optimum["success_rate"] <= optimum["ci_high"]).all()
    assert math.isnan(optimum.loc[10, "median_evals_to_optimum"])
    assert optimum.loc[250, "median_evals_to_optimum"] == pytest.approx(40.0)  # (20 + 60) / 2
    within = table[table["target"] == "within_1"]
    assert (within["success_rate"] == 1.0).all() and (within["ci_high"] == 1.0).all()
    assert (within["ci_low"] < 1.0).all()  # eight runs never make a sure thing
    curves = success_curves(runs, {"s": 250})
    at = curves[(curves["target"] == "optimum")].set_index("evaluations")["success_rate"]
    assert at.loc[1] == 0 and at.loc[250] == 6 / 8 and at.is_monotonic_increasing


if __name__ == "__main__":
    sys.exit(pytest.main([__file__]))


def test_a_job_uses_the_values_its_parent_prepared(monkeypatch):
    """The parent computes each worker's objective once before the pool forks; a job then
    reads no landscape of its own."""
    from ergohandover.study.personalise import sessions as personalise
    from ergohandover.twin.evaluate import Evaluator

    landscape = bowl_landscape()
    monkeypatch.setattr(personalise, "_VALUES", {})
    prepared = personalise.prepare_values("w1", "paper_postural", landscape)

    def no_reading(*args, **kwargs):
        raise AssertionError("a job read a landscape its parent had prepared")

    monkeypatch.setattr(personalise, "landscape_of", no_reading)
    job = personalise.PersonaliseJob("w1", Evaluator(), landscape.grid, "paper_postural",
                                     "random-order", 400, (3, 4), Prior((0, 1.1, 0.4),
                                                                       (0.05,) * 3))
    assert personalise.values_of(job) is prepared
    rows = personalise.run_personalise_job(job)
    assert [r["optimum_score"] for r in rows] == [5.0, 5.0]
    assert all(r["best_score"] == 5.0 for r in rows)  # random order tries every cell in time
