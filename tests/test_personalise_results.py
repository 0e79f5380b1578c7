"""The committed personalisation study: at least seven searchers (the population prior,
CMA-ES, PSO, random order and the paper's Q-learning among them) on at least 30 workers with at
least 10 paired runs each; with answers as a site gets them, five runs each and every row
read against no search; every summary row read again from the runs; the report's blocks and
the command's default searcher equal to what the results say."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))
import personalise_tables  # noqa: E402
from readme_blocks import block  # noqa: E402

FOLDER = ROOT / "results" / "personalise"
REQUIRED = {"prior", "cmaes", "pso", "random-order", "qlearning"}
COLUMNS = ["searcher", "target", "budget", "n_workers", "n_runs", "success_rate", "ci_low",
           "ci_high", "median_evals_to_optimum", "median_evals_to_within_1"]


def read(name: str) -> pd.DataFrame:
    return pd.read_csv(FOLDER / name, keep_default_na=False, na_values=[""])


def test_the_summary_covers_the_searchers_workers_and_budgets_asked_for():
    summary = read("summary.csv")
    assert set(COLUMNS) <= set(summary.columns)
    assert set(summary["searcher"]) >= REQUIRED and summary["searcher"].nunique() >= 7
    assert (summary["n_workers"] >= 30).all()
    assert (summary["n_runs"] >= 10 * summary["n_workers"]).all()
    cheap = summary[summary["searcher"] == "random-order"]
    assert set(cheap["budget"]) == {10, 25, 50, 100, 250, 1000}
    assert set(summary["target"]) == {"optimum", "within_1"}


def test_runs_are_paired_and_every_summary_row_is_read_from_them():
    runs = read("runs.csv")
    seeds = runs.groupby(["worker", "run"])["seed"].nunique()
    assert (seeds == 1).all()  # run r of a worker: one seed for every searcher
    summary = read("summary.csv")
    for row in summary.itertuples():
        mine = runs[runs["searcher"] == row.searcher]
        evals = mine[f"evals_to_{row.target}"].to_numpy(float)
        hit = ~np.isnan(evals) & (evals <= row.budget)
        assert row.n_runs == len(mine) and row.successes == hit.sum()
        assert row.success_rate == pytest.approx(hit.mean())
        assert row.ci_low <= row.success_rate <= row.ci_high
        # No evaluation count beyond the searcher's largest budget.
        assert (mine["evaluations"] <= summary.loc[summary["searcher"] == row.searcher,
                                                   "budget"].max()).all()
    # Reaching the optimum reaches within one point of it, never later.
    both = runs.dropna(subset=["evals_to_optimum"])
    assert (both["evals_to_within_1"] <= both["evals_to_optimum"]).all()


def test_the_optimum_found_is_each_workers_own_minimum():
    runs, workers = read("runs.csv"), read("workers.csv").set_index("worker")
    reached = runs.dropna(subset=["evals_to_optimum"])
    assert (reached["best_score"] == workers.loc[reached["worker"], "optimum_score"].to_numpy()
            ).all()
    assert (runs["best_score"] >= workers.loc[runs["worker"], "optimum_score"].to_numpy()).all()
    # The leave-one-out prior lies within a few centimetres of where the optimum is.
    assert workers["prior_to_optimum_m"].median() < 0.08


def test_the_report_blocks_and_the_commands_default_are_the_committed_results():
    for name, made in personalise_tables.blocks(ROOT / "results").items():
        assert block(name) == made, name
    from ergohandover.cli import personalise

    assert personalise_tables.command_default(
        read("measured_summary.csv")).removesuffix("+prior") == personalise.DEFAULT_SEARCHER


def test_the_best_searcher_meets_the_target_or_the_report_says_it_does_not():
    ranked = personalise_tables.ranking(read("summary.csv"))
    best = ranked.iloc[0]
    median = best["median_evals_to_optimum"]
    answer = personalise_tables.answer(read("summary.csv"))
    assert (not math.isnan(median)) and f"a median of {median:g}" in answer


def test_the_manifest_records_the_seed_and_each_searchers_time():
    manifest = json.loads((FOLDER / "manifest.json").read_text())
    assert manifest["seeds"]["runs"] == manifest["config"]["personalise"]["seed"]
    assert set(manifest["searcher_seconds"]) == set(read("summary.csv")["searcher"])


def test_a_bad_setting_of_the_part_is_one_line_and_exit_2(tmp_path):
    done = subprocess.run([sys.executable, "experiments/run_all.py", "--only", "personalise",
                           "--set", 'personalise.budget_caps={"nope": 5}', "--results",
                           str(tmp_path)],
                          cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 2
    assert done.stderr.strip().count("\n") == 0 and "'nope' names no searcher" in done.stderr
    assert not any(tmp_path.iterdir())


def test_the_measured_answers_cover_every_searcher_answer_model_budget_and_twin():
    from ergohandover.study.config import StudyConfig
    from ergohandover.study.personalise.measured_answers import answer_models, model_of

    part = StudyConfig.load(ROOT / "experiments" / "configs" / "default.json", ()).personalise
    runs, summary = read("measured_runs.csv"), read("measured_summary.csv")
    models = answer_models(part.measured_sds, part.measured_iccs, part.measured_imu)
    labels = {a.label for a in models}
    assert len(labels) >= 7 and {"exact", "posture SD 10 deg", "rater ICC 0.51"} <= labels
    assert any(a.kind == "imu" for a in models)
    headline = f"posture SD {part.headline_sd:g} deg"
    rules = {s: (["model", "model, stopped"] if s == "fitted-twin" else ["model"]
                 if s.startswith("pairwise") else ["model", "lowest", "confirm"])
             for s in part.measured_searchers}
    groups = {"in-model": labels, "out-of-model": labels, "impaired": {headline},
              "steps or other proportions": {headline}}
    keys = {(m, s, a, r, b) for m, answers in groups.items() for s in part.measured_searchers
            for a in answers for r in rules[s] for b in part.budgets_of(s, measured=True)}
    keys |= {(m, "no search", a, "prior's location", 1) for m, answers in groups.items()
             for a in answers}
    assert set(zip(summary["model"], summary["searcher"], summary["answers"], summary["rule"],
                   summary["budget"], strict=True)) == keys
    inside = summary["model"] == "in-model"
    assert (summary.loc[inside, "n_workers"] == part.workers).all()
    outside = part.measured_variant_workers * len(part.measured_variants)
    assert (summary.loc[summary["model"] == "out-of-model", "n_workers"] == outside).all()
    assert outside >= 15
    impaired = summary["model"] == "impaired"
    assert (summary.loc[impaired, "n_workers"] == 3 * part.measured_unknown_workers).all()
    assert part.measured_unknown_workers >= 5
    searched = summary["searcher"] != "no search"
    # The headline's answers, and in model the published IMU's (a target is set for both).
    headline_like = (summary["answers"] == headline) | (
        (summary["answers"] == "IMU") & (summary["model"] == "in-model"))
    runs_each = np.where(headline_like, part.headline_runs, part.measured_runs)
    assert part.headline_runs == 5
    assert (summary.loc[searched, "n_runs"] == (runs_each * summary["n_workers"])[searched]).all()
    assert set(runs["twin"]) == {"in-model", *part.measured_variants, *part.measured_unknown}
    assert (runs["regret"] >= 0).all() and (runs["handovers"] <= runs["budget"]).all()
    # Exact answers are the truth; a true score is the worker's (or changed twin's) own.
    exact = runs[(runs["answers"] == "exact") & (runs["rule"] == "lowest")]
    assert (exact["answer"] == exact["true_score"]).all()
    assert (runs.groupby(["worker", "twin"])["optimum_score"].nunique() == 1).all()
    runs = runs.assign(model=runs["twin"].map(model_of))
    shares = runs.assign(zero=runs["regret"] == 0).groupby(
        ["model", "searcher", "answers", "rule", "budget"], sort=False)["zero"].mean()
    for row in summary[searched].itertuples():
        key = (row.model, row.searcher, row.answers, row.rule, row.budget)
        assert row.p_regret_0 == pytest.approx(shares[key])
        assert row.ci_low <= row.p_regret_0 <= row.ci_high
        assert row.gain_ci_low <= row.gain <= row.gain_ci_high
        assert row.harm_ci_low <= row.harm <= row.harm_ci_high


def test_the_gain_over_no_search_is_paired_per_worker_from_the_runs():
    from ergohandover.study.config import StudyConfig

    part = StudyConfig.load(ROOT / "experiments" / "configs" / "default.json", ()).personalise
    runs, summary = read("measured_runs.csv"), read("measured_summary.csv")
    workers = read("workers.csv").set_index("worker")
    nothing = summary[(summary["searcher"] == "no search") & (summary["model"] == "in-model")]
    # No search in model: each worker's regret at its prior's location, from workers.csv's
    # prior and the runs' optimum (the exact answers' true scores are the worker's own).
    assert (nothing["n_workers"] == part.workers).all()
    row = summary[(summary["model"] == "in-model") & (summary["searcher"] == "fitted-twin")
                  & (summary["rule"] == "model") & (summary["answers"] == "posture SD 5 deg")
                  & (summary["budget"] == 10)].iloc[0]
    mine = runs[(runs["twin"] == "in-model") & (runs["searcher"] == "fitted-twin")
                & (runs["rule"] == "model") & (runs["answers"] == "posture SD 5 deg")
                & (runs["budget"] == 10)]
    baseline = nothing[nothing["answers"] == "posture SD 5 deg"].iloc[0]
    # The gain's mean over workers of (baseline - regret) equals the difference of the means.
    assert row["gain"] == pytest.approx(baseline["mean_regret"] - mine["regret"].mean())
    assert set(mine["worker"]) == set(workers.index)
