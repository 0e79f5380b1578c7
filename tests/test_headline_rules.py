"""Every headline row states its N, its uncertainty and the condition that reverses it, and the
reversing conditions are looked for in results/ here, apart from the rules: a rerun that turns
up a new one fails until the row names it."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "results"
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))
sys.path.insert(0, str(ROOT / "tests"))

import headlines  # noqa: E402
import readme_blocks  # noqa: E402
import robustness_verdicts  # noqa: E402

from ergohandover.study.population.who_pays import PLANNED  # noqa: E402

DECLARED = {h.label: h for h in headlines.headlines(RESULTS)}
ROWS = {label: " ".join((h.claim, h.n, h.uncertainty, h.baseline, *h.reverses))
        for label, h in DECLARED.items()}
"""Each headline's whole text: its README cells give what fits and link to the rest."""


def test_the_report_lists_every_headline_with_all_it_rests_on():
    table = readme_blocks.block("headline-rules")
    assert table == headlines.blocks(RESULTS)["headline-rules"]
    for label, h in DECLARED.items():
        line = next(x for x in table.splitlines() if x.startswith(f"| {label} |"))
        for part in (h.n, h.uncertainty, h.baseline, *h.reverses):
            assert part in line, (label, part)


SCORE_LABELS = {"paper_postural": "paper score", "reba": "REBA", "rula": "RULA"}


def reversals() -> list[tuple[str, str, str]]:
    """(score label, condition token, starts) wherever the optimum measures worse than a
    shortest-distance location, under any error model of the results: read from the CSVs here,
    apart from the tables' code."""
    stress = pd.read_csv(RESULTS / "robustness" / "comparisons.csv")
    stress = stress[stress["perturbation"] == "posture error"].assign(
        token=lambda f: f["angle_sd_deg"].map(lambda sd: f"{sd:g}°"))
    measured = pd.read_csv(RESULTS / "robustness" / "measured_comparisons.csv").assign(
        token=lambda f: f["error_model"].map(robustness_verdicts.MODEL_PHRASES))
    assert measured["token"].notna().all(), "an error model without a phrase"
    rows = pd.concat([stress, measured], ignore_index=True)
    worse = rows[(rows["a"] == "nominal optimum") & rows["b"].str.startswith("shortest")
                 & (rows["ci_low"] > 0)]
    return [(SCORE_LABELS[score], token, ", ".join(b.rsplit(" ", 1)[1] for b in group["b"]))
            for (score, token), group in worse.groupby(["score", "token"])]


@pytest.mark.parametrize("label", ["optimised vs shortest distance", "under error"])
def test_every_error_model_that_reverses_the_optimised_location_is_named(label):
    clauses = ROWS[label].split("; ")
    found = reversals()
    assert found, "the results hold reversals; this test would pass vacuously otherwise"
    for score, token, starts in found:
        plural = "s" if "," in starts else ""
        assert any(f"{score} worse from start{plural} {starts} " in c and token in c
                   for c in clauses), (label, score, token, starts)


def test_the_scores_a_stepping_worker_reverses_are_named():
    head = pd.read_csv(RESULTS / "stance" / "headline.csv")
    step = head[(head["optimised_location"] == "optimised") & (head["stance"] == "step")]
    for score, name in (("reba", "REBA"), ("rula", "RULA")):
        beats = int(step.loc[step["score"] == score, "beats"].sum())
        if beats < (step["score"] == score).sum():
            for label in ("optimised vs shortest distance", "a worker who steps"):
                said = re.search(rf"on {name} from (?:only )?(\d+)", ROWS[label])
                assert said and int(said.group(1)) == beats, (label, score)


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
    planned = tests[tests["model"] == PLANNED]
    sex = planned[planned["question"] == "sex beyond body size"]
    row = ROWS["population"]
    assert "rather than sex" not in row  # an interval, not a verdict of absence
    if (sex["p_holm"] >= 0.05).all():
        assert "sex matters" not in row and "an interval that allows a sex effect" in row
    # The family: both questions at every distinct location whose penalty varies at all.
    penalties = pd.read_csv(RESULTS / "population" / "penalties.csv")
    varying = penalties.groupby(["objective", "x", "y", "z"])["penalty"].agg(
        lambda p: p.max() > p.min())
    assert (planned["family"] == 2 * int(varying.sum())).all()
    assert len(planned) == 2 * int(varying.sum())


def test_every_variant_that_moves_the_minimum_is_named():
    variants = pd.read_csv(RESULTS / "sensitivity" / "sensitivity.csv")
    default = variants[variants["variant"] == "default"]["paper_postural_min"].iloc[0]
    moved = set(variants.loc[variants["paper_postural_min"] != default, "variant"])
    assert moved == set(headlines.MINIMUM_VARIANTS)


def test_a_participant_comparison_a_step_reverses_is_named():
    head = pd.read_csv(RESULTS / "stance" / "headline.csv")
    others = head[(head["optimised_location"] == "own optimised") & (head["score"] == "reba")
                  & (head["stance"] == "step")]
    if not others["beats"].all():
        assert f"once they may step, in {int(others['beats'].sum())} of {len(others)}" in \
            ROWS["participants"]
