"""The committed population study: a workforce of at least 30, every one-size choice and its
penalties consistent with the landscapes' optima, intervals around their estimates, and the
report's blocks equal to what the tables script makes of results/population/. Bad input to the
study's commands is a one-line error that writes nothing."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))
import population_tables  # noqa: E402
from readme_blocks import block  # noqa: E402

FOLDER = ROOT / "results" / "population"


def read(name: str) -> pd.DataFrame:
    return pd.read_csv(FOLDER / name, keep_default_na=False, na_values=[""])


def test_the_workforce_has_at_least_100_workers_whose_proportions_vary():
    workers = read("workers.csv")
    sampled = workers[workers["reference"] == 0]
    assert len(sampled) >= 100 and set(sampled["sex"]) == {"female", "male"}
    assert list(workers.loc[workers["reference"] == 1, "worker"]) == ["p50-male"]
    # Every worker's own measurements, and proportions that vary as the survey's (elbow height
    # 0.613 +/- 0.010 of stature): not one fixed share of stature.
    for column in ("shoulder_height_m", "wrist_height_m", "knee_height_m", "arm_length_m"):
        assert sampled[column].notna().all(), column
    assert (sampled["elbow_ratio"] == (sampled["elbow_height_m"] / sampled["stature_m"])
            .round(5)).all()
    assert 0.006 < sampled["elbow_ratio"].std() < 0.014
    assert 0.004 < sampled["arm_ratio"].std() < 0.02


def test_sex_and_proportions_are_analysed_beside_stature():
    fits = read("proportions.csv")
    assert set(fits["term"]) == {"intercept", "stature_m", "male", "elbow_ratio", "arm_ratio"}
    assert (fits["ci_low"] <= fits["coef"]).all() and (fits["coef"] <= fits["ci_high"]).all()
    # A p-value where the penalty varies; none where every worker's penalty is the same (REBA's
    # one-size choices cost no one anything: the standard error is 0).
    assert fits["p"].dropna().between(0, 1).all()
    assert (fits.loc[fits["p"].isna(), "se"] == 0).all()
    twins = read("fixed_ratio_twin.csv").set_index(["proportions", "objective"])
    # The fixed-ratio twin's elbow is its joint at 0.632 of stature; the body model's standing
    # elbow height is lower (0.613 of stature on average in the survey).
    old = twins.loc[("drillis-contini", "paper_postural")]
    new = twins.loc[("ansur2", "paper_postural")]
    assert old["elbow_height_m"] == pytest.approx(0.632 * 1.756, abs=1e-4)
    assert new["elbow_height_m"] < old["elbow_height_m"]


def test_no_worker_scores_below_their_own_optimum_anywhere():
    penalties = read("penalties.csv")
    workers = read("workers.csv").set_index("worker")
    assert (penalties["penalty"].dropna() >= 0).all()
    for objective, rows in penalties.groupby("objective"):
        own = workers.loc[rows["worker"], f"{objective}_opt"].to_numpy()
        assert (rows["own_optimum"].to_numpy() == own).all()
        taken = rows[objective].notna()
        assert (rows[objective][taken] - own[taken.to_numpy()]
                == rows["penalty"][taken]).all()


def test_each_choice_is_best_by_its_own_rule_and_intervals_hold_their_estimates():
    one_size = read("one_size.csv")
    for _, rows in one_size.groupby("objective"):
        rows = rows.set_index("choice")
        assert rows.loc["mean", "mean_score"] <= rows["mean_score"].min() + 1e-12
        assert rows.loc["p95", "p95_score"] <= rows["p95_score"].min()
        assert rows.loc[["mean", "p95"], "infeasible_for"].eq(0).all()
    for stem in ("mean", "share_penalised", "share_penalised_2plus"):
        value = one_size["mean_penalty" if stem == "mean" else stem]
        assert (one_size[f"{stem}_ci_low"] <= value + 1e-12).all()
        assert (value <= one_size[f"{stem}_ci_high"] + 1e-12).all()


def test_the_report_population_blocks_are_the_committed_results():
    for name, made in population_tables.blocks(ROOT / "results").items():
        assert block(name) == made, name


@pytest.mark.parametrize(("command", "message"), [
    (["experiments/run_all.py", "--only", "population", "--set", "population.size=0"],
     "run_all: error: population.size = 0 is outside the valid range"),
    (["experiments/run_all.py", "--only", "population", "--engine", "ray", "--address",
      "nonsense"], "run_all: error: address = 'nonsense' is not valid"),
    (["experiments/run_all.py", "--only", "population", "--engine", "ray", "--address",
      "host:port"], "run_all: error: address = 'host:port' is not valid"),
    (["experiments/run_all.py", "--only", "population", "--config", "no/such/config.json"],
     "run_all: error: config = 'no/such/config.json' is not a readable JSON file"),
])
def test_bad_population_input_is_one_line_and_writes_nothing(tmp_path, command, message):
    out = subprocess.run([sys.executable, str(ROOT / command[0]), *command[1:], "--results",
                          str(tmp_path / "results")], capture_output=True, text=True,
                         cwd=ROOT, timeout=120)
    assert out.returncode == 2
    assert out.stderr.strip().startswith(message) and len(out.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "results").exists()
