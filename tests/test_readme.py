"""The README is an honest front door: its test command is the one CI runs, it stays short, its
links lead somewhere, and its headline table is the declared headlines rendered from the
committed results, each naming its baseline."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
RESULTS = ROOT / "results"
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))

import headlines  # noqa: E402
import personalise_tables  # noqa: E402
import population_tables  # noqa: E402
import readme_blocks  # noqa: E402


def bash_blocks(text: str) -> list[str]:
    return [b.strip() for b in re.findall(r"```bash\n(.*?)```", text, re.S)]


def test_readme_starts_with_the_two_commands_and_ci_runs_the_test_one():
    main_job, tests = bash_blocks(README)[:2]
    assert main_job.endswith("experiments/run_all.py")
    assert "pytest" in tests
    ci_lines = (ROOT / ".ci" / "run").read_text().splitlines()
    assert tests in ci_lines, "the README's test command must appear verbatim in .ci/run"


def test_readme_is_a_front_door_of_at_most_250_lines():
    assert len(README.splitlines()) <= 250


# Links -------------------------------------------------------------------------------------

def anchors(text: str) -> set[str]:
    """The anchors GitHub gives the headings of a Markdown page."""
    seen: dict[str, int] = {}
    out = set()
    for heading in re.findall(r"^#{1,6} (.+)$", re.sub(r"```.*?```", "", text, flags=re.S),
                              flags=re.M):
        slug = re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        out.add(slug if n == 0 else f"{slug}-{n}")
    return out


def broken_links(page: Path) -> list[str]:
    """Relative links of ``page`` whose file, or whose anchor in a Markdown file, is missing."""
    text = page.read_text()
    broken = []
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", target):
            continue
        path, _, anchor = target.partition("#")
        file = (page.parent / path).resolve() if path else page
        missing = not file.exists() or (anchor and file.suffix == ".md"
                                        and anchor not in anchors(file.read_text()))
        if missing:
            broken.append(target)
    return broken


def test_readme_links_lead_to_files_and_sections_that_exist():
    assert broken_links(ROOT / "README.md") == []


# The headline table ------------------------------------------------------------------------

def headline_rows() -> dict[str, list[str]]:
    """Each row of the headline table, by its label: its cells (label, the paper, we measured,
    compared with, reverses)."""
    table = readme_blocks.readme_block(README, "headlines").strip("\n")
    rows = {}
    for line in table.splitlines()[2:]:
        row = [cell.strip() for cell in line.strip().strip("|").split(" | ")]
        rows[re.match(r"\[(.+?)\]", row[0]).group(1)] = row
    return rows


DECLARED = headlines.headlines(RESULTS)


def test_the_headline_table_is_the_declared_headlines_rendered_from_results():
    assert readme_blocks.block("headlines") == headlines.blocks(RESULTS)["headlines"]
    assert readme_blocks.block("recommendation") == headlines.blocks(RESULTS)["recommendation"]
    assert list(headline_rows()) == [h.label for h in DECLARED]


def test_every_headline_cell_is_short_and_every_headline_names_its_baseline():
    for label, row in headline_rows().items():
        assert len(row) == 5, label
        for cell in row:
            assert len(cell) <= headlines.CELL, (label, len(cell), cell)
    for h in DECLARED:
        assert h.n and h.uncertainty and h.baseline, h.label
        assert h.reverses or h.none_because, h.label
        for name in h.files:
            assert (RESULTS / name).exists(), (h.label, name)


def test_every_question_with_a_headline_declares_one_and_no_other_does():
    from ergohandover.study.registry import QUESTIONS

    assert {h.question for h in DECLARED} == {q.name for q in QUESTIONS if q.headline}


def test_a_reversing_condition_that_does_not_fit_is_counted_and_linked():
    fitted = headlines.fitted(["a" * 130, "b" * 130, "c" * 130], more="(see)")
    assert fitted == "a" * 130 + "; and 2 more (see)"
    assert len(headlines.fitted(["a" * 100] * 5, more="(see)")) <= headlines.CELL
    assert headlines.fitted(["x", "y"]) == "x; y"


def test_an_exact_interval_is_never_degenerate_at_a_bound():
    low, high = headlines.exact_interval(1000, 1000)
    assert high == 1.0 and 0.996 < low < 0.9965  # (0.025)^(1/1000)
    low, high = headlines.exact_interval(0, 30)
    assert low == 0.0 and 0.11 < high < 0.12
    low, high = headlines.exact_interval(13, 30)
    assert low < 13 / 30 < high


# The wording of the headlines: what each compares with, read from results/ ----------------


def row_text(label: str) -> str:
    return " ".join(headline_rows()[label])


def test_the_workforce_row_gives_an_exact_interval_and_reads_measurement_as_agreement():
    at = pd.read_csv(RESULTS / "accommodation" / "locations.csv")
    rec = at[at["location"] == "nominal optimum"].iloc[0]
    n = int(rec["workers"])
    suited = round(rec["exact_share"] * n)
    text = row_text("a workforce's zone")
    assert f"{suited:,} of {n:,} workers" in text
    if suited == n:
        assert "100–100" not in text and "exact 95 % 99.6 %–100 %" in text
    assert f"agrees in {headlines.pct(rec['measured_share'])} of measurements" in text
    assert f"misclassifies {headlines.pct(1 - rec['measured_share'])}" in text
    assert "the error-free score" in text


def test_the_one_size_row_names_the_reference_optimum_beside_its_held_out_cost():
    one_size = pd.read_csv(RESULTS / "robustness" / "one_size.csv")
    rows = one_size[one_size["objective"] == "paper_postural"].set_index("choice")
    text = row_text("population")
    assert f"costs {rows.loc['mean', 'split_half_held_out']:.2f} points" in text
    assert ("the 50th-percentile man's optimum, chosen on no worker: "
            f"{rows.loc['reference', 'in_sample_mean_penalty']:.2f}") in text
    # The analysis plan followed the straight-line result: post hoc, and an interval, not a
    # verdict of no sex effect.
    assert "post hoc" in text and "rather than sex" not in text
    assert "pre-specified" not in text and "as planned" not in text
    tests = pd.read_csv(RESULTS / "population" / "who_pays_tests.csv")
    sex = population_tables.planned_sex(tests)
    assert f"({sex['ci_low']:+.2f} to {sex['ci_high']:+.2f})" in text


def test_rows_read_under_error_name_what_the_error_model_assumes():
    for label in ("under error",):
        text = row_text(label)
        assert "IMU-like" in text and "assumed" in text
        assert "as an IMU system would measure" not in text


def test_the_personalising_row_is_compared_with_not_searching():
    text = row_text("personalising")
    cells = headline_rows()["personalising"]
    assert "no search, one handover at the prior's location" in cells[3]
    measured = pd.read_csv(RESULTS / "personalise" / "measured_summary.csv")
    nothing = measured[(measured["model"] == "in-model") & (measured["searcher"] == "no search")
                       & (measured["answers"] == personalise_tables.HEADLINE_ANSWERS)].iloc[0]
    assert headlines.pct(nothing["p_regret_0"]) in text
    # It leads with the gain over no search, within the headline's handovers, with N.
    best = measured[(measured["model"] == "in-model") & (measured["rule"] == "model")
                    & (measured["answers"] == personalise_tables.HEADLINE_ANSWERS)
                    & (measured["budget"] == personalise_tables.HEADLINE_BUDGET)
                    & (measured["searcher"] != "random-order")].sort_values(
        ["p_regret_0", "mean_regret"], ascending=[False, True]).iloc[0]
    assert cells[2].startswith(f"postures measured with 5° of error, "
                               f"{personalise_tables.HEADLINE_BUDGET} handovers: ")
    assert f"gains {best['gain']:+.2f} points of true regret over no search" in cells[2]
    assert f"N = {int(best['n_workers'])} workers" in text
