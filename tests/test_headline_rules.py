"""Every headline row states its N, its uncertainty and the condition that reverses it, and the
reversing conditions are looked for in results/ here, apart from the rules: a rerun that turns
up a new one fails until the row names it."""

from __future__ import annotations

import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "results"
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))
sys.path.insert(0, str(ROOT / "tests"))

import headline_rules  # noqa: E402
import readme_blocks  # noqa: E402
from test_readme import headline_rows  # noqa: E402

RULES = headline_rules.rules(RESULTS)
ROWS = {label: ours for label, (_, _, ours) in headline_rows().items()}


def test_every_headline_row_has_a_rule_and_every_rule_a_row():
    assert list(RULES) == list(ROWS)


@pytest.mark.parametrize("label", list(RULES))
def test_the_row_states_n_uncertainty_and_what_reverses_it(label):
    rule, row = RULES[label], ROWS[label]
    assert rule.n in row, (label, rule.n)
    assert rule.uncertainty in row, (label, rule.uncertainty)
    if rule.reverses is None:
        assert rule.none_because, label
    else:
        for part in rule.reverses.split("; "):
            assert part in row, (label, part)
    for name in rule.files:
        assert (RESULTS / name).exists(), (label, name)


def test_a_posture_error_that_reverses_the_optimised_location_is_named():
    compared = pd.read_csv(RESULTS / "robustness" / "comparisons.csv")
    worse = compared[(compared["perturbation"] == "posture error")
                     & (compared["a"] == "nominal optimum")
                     & compared["b"].str.startswith("shortest")
                     & (compared["score"] == "paper_postural") & (compared["ci_low"] > 0)]
    for sd, rows in worse.groupby("angle_sd_deg"):
        starts = ", ".join(b.rsplit(" ", 1)[1] for b in rows["b"])
        for label in ("optimised vs shortest distance", "under error"):
            assert f"at {sd:g}° it is worse from start" in ROWS[label], (label, sd)
            assert starts in ROWS[label], (label, starts)


def test_starts_the_measured_error_reverses_are_named():
    compared = pd.read_csv(RESULTS / "robustness" / "measured_comparisons.csv")
    worse = compared[(compared["error_model"] == compared["error_model"].iloc[0])
                     & (compared["a"] == "nominal optimum")
                     & compared["b"].str.startswith("shortest")
                     & (compared["score"] == "paper_postural") & (compared["ci_low"] > 0)]
    if len(worse):
        starts = ", ".join(b.rsplit(" ", 1)[1] for b in worse["b"])
        for label in ("optimised vs shortest distance", "under error"):
            assert "on the paper score it is worse from start" in ROWS[label], label
            assert starts in ROWS[label], (label, starts)


def test_the_scores_a_stepping_worker_reverses_are_named():
    head = pd.read_csv(RESULTS / "stance" / "headline.csv")
    step = head[(head["optimised_location"] == "optimised") & (head["stance"] == "step")]
    for score, name in (("reba", "REBA"), ("rula", "RULA")):
        rows = step[step["score"] == score]
        if not rows["beats"].all():
            for label in ("optimised vs shortest distance", "a worker who steps"):
                assert f"on {name} from" in ROWS[label], (label, score)
                assert f"{int(rows['beats'].sum())}" in ROWS[label].split(f"on {name} from")[1][
                    :12], (label, score)


def test_learning_ties_at_the_ceiling_are_counted_apart_from_equivalence():
    compared = pd.read_csv(RESULTS / "learning" / "comparisons.csv")
    walk = compared[(compared["agent"] == "qlearning") & (compared["versus"] == "randomwalk")]
    top = ((walk["successes_agent"] >= walk["n"] - 1)
           & (walk["successes_versus"] >= walk["n"] - 1))
    row = ROWS["does it learn?"]
    if top.any():
        assert f"in {int(top.sum())} both reach the target in all but at most one run" in row
    below = walk[~top & walk["verdict"].str.startswith("equivalent")]
    assert (f"equivalent within ±10 points of success rate in {len(below)}" in row) == \
        (len(below) > 0)


def test_a_sex_effect_is_claimed_only_if_the_planned_test_finds_it():
    tests = pd.read_csv(RESULTS / "population" / "who_pays_tests.csv")
    planned = tests[(tests["model"] == "spline, HC3 errors")
                    & (tests["question"] == "sex beyond body size")]
    row = ROWS["population"]
    if (planned["p_holm"] >= 0.05).all():
        assert "sex matters" not in row
        assert "by body size rather than sex" in row
    assert planned["family"].iloc[0] == (tests["model"] == "spline, HC3 errors").sum()


def test_every_variant_that_moves_the_minimum_is_named():
    variants = pd.read_csv(RESULTS / "sensitivity" / "sensitivity.csv")
    default = variants[variants["variant"] == "default"]["paper_postural_min"].iloc[0]
    moved = set(variants.loc[variants["paper_postural_min"] != default, "variant"])
    assert moved == set(headline_rules.MINIMUM_VARIANTS)


def test_a_participant_comparison_a_step_reverses_is_named():
    head = pd.read_csv(RESULTS / "stance" / "headline.csv")
    others = head[(head["optimised_location"] == "own optimised") & (head["score"] == "reba")
                  & (head["stance"] == "step")]
    if not others["beats"].all():
        assert f"once they may step, in {int(others['beats'].sum())} of {len(others)}" in \
            ROWS["participants"]


def test_the_report_carries_the_rules_table():
    assert readme_blocks.block("headline-rules") == headline_rules.blocks(RESULTS)[
        "headline-rules"]
