"""docs/report.md tells the truth: its example output is real, every table and quoted number is
the committed result in results/, its generated blocks are what the tables scripts make of
results/, and its links and contents lead somewhere."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pandas as pd
import pytest
from test_readme import anchors, broken_links

from ergohandover.ergonomics import score_postures
from ergohandover.io.posture_csv import read_postures
from ergohandover.study.registry import PARTS

ROOT = Path(__file__).resolve().parents[1]
REPORT_PATH = ROOT / "docs" / "report.md"
REPORT = REPORT_PATH.read_text()
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))

import capture_tables  # noqa: E402
import learning_tables  # noqa: E402
import people_tables  # noqa: E402
import personalise_tables  # noqa: E402
import population_tables  # noqa: E402
import readme_blocks  # noqa: E402
import robustness_tables  # noqa: E402
import stance_tables  # noqa: E402
import validation_tables  # noqa: E402


def test_report_generated_blocks_are_the_committed_results():
    made = {**learning_tables.blocks(ROOT / "results"),
            **population_tables.blocks(ROOT / "results"),
            **personalise_tables.blocks(ROOT / "results"),
            **robustness_tables.blocks(ROOT / "results"),
            **stance_tables.blocks(ROOT / "results"),
            **validation_tables.blocks(ROOT / "results"),
            **capture_tables.blocks(ROOT / "results"),
            **people_tables.blocks(ROOT / "results")}
    for name, block in made.items():
        if name != "capture-claim":  # the README's paragraph on captured postures
            assert readme_blocks.where(name) == REPORT_PATH, name
        assert readme_blocks.block(name) == block, name


def test_neither_page_reads_a_measured_share_or_a_post_hoc_test_as_something_else():
    """The wording the results allow: a share of measurements agrees under an IMU-like error
    model (not "as an IMU system would measure them"), the who-pays tests were planned after
    the straight-line result (not pre-specified), and a sex effect is an interval."""
    for page in (REPORT, (ROOT / "README.md").read_text()):
        text = " ".join(page.split())
        for wrong in ("as an IMU system would measure", "measured as an IMU system measures",
                      "pre-specified", "as planned", "rather than sex", "(100–100 %)"):
            assert wrong.lower() not in text.lower(), wrong
    assert "post hoc" in REPORT and "IMU-like error model" in REPORT


def test_every_action_limit_exceeded_and_knife_edge_is_flagged_in_the_manikins_table():
    from ergohandover.workload.flags import KNIFE_EDGE_CM, LIFTING_INDEX_SCOPE

    table = pd.read_csv(ROOT / "results" / "manikins" / "manikins.csv")
    block = " ".join(readme_blocks.block("manikins-table").split())
    assert LIFTING_INDEX_SCOPE in block
    over = table[table["back_compression_n"] > 3400]
    assert len(over), "the results hold an exceedance; this test would pass vacuously"
    for value in over["back_compression_n"]:
        assert f"L5/S1 compression {value:,.0f} N over NIOSH's 3,400 N action limit" in block
    edge = table[(table["niosh_h_cm"] - 63).abs() <= KNIFE_EDGE_CM]
    assert len(edge)
    for value in edge["niosh_h_cm"].unique():
        assert f"knife edge: H {value:.2f} cm" in block


def test_rewrite_replaces_each_block_in_the_page_that_holds_it(tmp_path):
    readme, report = tmp_path / "README.md", tmp_path / "report.md"
    readme.write_text("a <!-- one -->old<!-- /one --> b\n")
    report.write_text("c <!-- two -->\nold\n<!-- /two --> d\n")
    pages = (readme, report)
    assert readme_blocks.rewrite({"one": "1", "two": "\n2\n"}, pages) == [readme, report]
    assert readme.read_text() == "a <!-- one -->1<!-- /one --> b\n"
    assert readme_blocks.block("two", pages) == "\n2\n"
    assert readme_blocks.rewrite({"one": "1"}, pages) == []  # unchanged: nothing written
    for bad in ({"one": "x", "three": "y"}, {"one": "x", "two": "y"}):
        if "two" in bad:  # a block in two pages is as wrong as a block in none
            report.write_text(report.read_text() + "<!-- one -->z<!-- /one -->\n")
        before = [page.read_text() for page in pages]
        with pytest.raises(LookupError, match="exactly one page"):
            readme_blocks.rewrite(bad, pages)
        assert [page.read_text() for page in pages] == before  # nothing written


def test_report_links_lead_to_files_and_sections_that_exist():
    assert broken_links(REPORT_PATH) == []


def test_report_contents_list_every_section():
    contents = REPORT.split("## Contents")[1].split("\n## ")[0]
    listed = set(re.findall(r"\]\(#([^)]+)\)", contents))
    sections = {a for a in anchors("\n".join(re.findall(r"^## .+$", REPORT, re.M)))}
    assert sections - {"contents"} <= listed
    assert listed <= anchors(REPORT)


def test_report_example_csv_is_the_example_file():
    block = re.search(r"```csv\n(.*?)```", REPORT, re.S).group(1)
    assert block == (ROOT / "examples" / "postures.csv").read_text()


def test_report_example_scores_are_the_real_output():
    table_text = REPORT.split("<!-- example-scores")[1].split("\n\n")[0]
    rows = [line.strip("|").split("|") for line in table_text.splitlines()[1:]
            if line.startswith("|") and not line.startswith("|---")]
    header, *body = [[cell.strip() for cell in row] for row in rows]
    text, posture = read_postures(ROOT / "examples" / "postures.csv")
    scores = pd.DataFrame(score_postures(posture))
    assert len(body) == len(text) == 3
    for i, row in enumerate(body):
        assert row[0] == text["name"][i]
        for name, cell in zip(header[1:], row[1:], strict=True):
            assert int(cell) == scores[name][i], (text["name"][i], name)


def test_report_baseline_table_is_the_committed_result():
    table = pd.read_csv(ROOT / "results" / "baselines" / "baselines.csv")
    block = REPORT.split("The table from\nthe committed run")[1].split("\n\n")[1]
    rows = [line.strip("|").split("|") for line in block.splitlines()[2:]]
    assert len(rows) == 5
    for row, (_, group) in zip(rows, table.groupby(["start_x", "start_y", "start_z"],
                                                   sort=False), strict=True):
        cells = [c.strip() for c in row]
        opt = group[group["method"] == "optimised"].iloc[0]
        short = group[group["method"] == "shortest_distance"].iloc[0]
        assert cells[1].split()[0] == str(int(opt["paper_postural"]))
        assert cells[3].split()[0] == str(int(short["paper_postural"]))
        assert cells[4] == f"{int(opt['reba'])} / {int(short['reba'])}"
        assert cells[5] == f"{int(opt['rula'])} / {int(short['rula'])}"
        robot = [("yes" if row["robot_feasible"] else "no") for row in (opt, short)]
        assert cells[6] == " / ".join(robot)


def test_report_landscape_table_is_the_committed_result():
    stats = pd.read_csv(ROOT / "results" / "landscape" / "stats.csv").set_index("score")
    header = REPORT.split("**The landscape** of the default worker and box")[1]
    first = stats.iloc[0]
    assert header.startswith(f" (N = {int(first['feasible']):,} feasible points, "
                             f"{first['feasible_fraction']:.1%})")
    block = header.split("| score | minimum |")[1].split("\n\n")[0]
    rows = [[c.strip() for c in line.strip("|").split("|")]
            for line in block.splitlines()[2:]]
    assert [r[0] for r in rows] == ["paper_postural", "reba", "reba_ab", "rula"]
    for name, minimum, count, share, best in rows:
        row = stats.loc[name]
        assert int(minimum) == row["min"] and int(count.replace(",", "")) == row["n_at_min"]
        digits = 2 if row["fraction_at_min"] < 0.1 else 1
        assert share == f"{row['fraction_at_min']:.{digits}%}", name
        assert best == f"({row['best_x']:.3f}, {row['best_y']:.3f}, {row['best_z']:.3f})"


def tables_md_block(title: str) -> str:
    """The table of results/tables.md that follows the line starting with ``title``."""
    text = (ROOT / "results" / "tables.md").read_text()
    after = text.split("\n" + title, 1)[1]
    return after.split("\n\n", 2)[1].strip("\n")


def marked_table(marker: str) -> str:
    """The table that follows ``<!-- marker ... -->`` in the report."""
    after = REPORT.split(f"<!-- {marker}", 1)[1].split("-->", 1)[1]
    return after.strip("\n").split("\n\n", 1)[0]


def test_report_gaze_and_boundary_table_is_the_committed_result():
    assert marked_table("gaze-table") == tables_md_block("Both boundaries, gaze on and off")


def test_report_sensitivity_table_is_the_committed_result():
    assert marked_table("sensitivity-table") == tables_md_block("## Sensitivity")


def test_report_validation_table_is_the_committed_result():
    assert marked_table("validation-table") == tables_md_block("## Validation")


def test_report_gaze_explanation_quotes_the_committed_result():
    effect = pd.read_csv(ROOT / "results" / "landscape" / "gaze_effect.csv").iloc[0]
    text = " ".join(REPORT.split("**Gaze decides how often the minimum is reached.**")[1]
                    .split("## Sensitivity")[0].split())
    for quoted in (f"on {int(effect['points']):,} points",
                   f"{effect['y_min']:.2f}–{effect['y_max']:.2f} m high",
                   f"{effect['z_min']:.2f}–{effect['z_max']:.2f} m in front",
                   f"by {effect['neck_flexion_on']:.1f}° on average",
                   f"(past 20° at {effect['neck_over_20_on_share']:.0%} of those points)".replace(
                       "%", " %"),
                   f"leans the trunk {effect['trunk_flexion_on']:.1f}°",
                   f"elbows to {effect['left_elbow_flexion_on']:.0f}°",
                   f"a median score of {effect['paper_postural_on_median']:.0f}"):
        assert quoted in text, quoted


def test_report_knee_height_postures_quote_the_committed_result():
    table = pd.read_csv(ROOT / "results" / "validation" / "knee_height.csv")
    feasible = table[table["feasible"] == 1]
    text = " ".join(REPORT.split("<!-- knee-height")[1].split("-->", 1)[1].split()[:12])
    for column, label in (("knee_flexion", "knee"), ("hip_flexion", "hip"),
                          ("lumbar_flexion", "lumbar")):
        low, high = feasible[column].min(), feasible[column].max()
        assert f"{label} {low:.0f}–{high:.0f}°" in text, column
    index = feasible["postural_index"]
    assert f"postural index {index.min():.2f}–{index.max():.2f}" in text
    assert set(table["worker"]) == {"p5-female", "p50-female", "p50-male", "p95-male"}


def test_report_carry_table_is_the_committed_result():
    table = pd.read_csv(ROOT / "results" / "baselines" / "baselines.csv",
                        keep_default_na=False, na_values=[""])
    block = REPORT.split("Each carry of the table")[1].split("\n\n")[1]
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in block.splitlines()[2:]]
    assert len(rows) == len(table) == 10
    for cells, (i, row) in zip(rows, table.iterrows(), strict=True):
        assert cells[0] == str(i // 2 + 1) and cells[1] == row["method"].replace("_", " ")
        assert cells[2] == ("yes" if row["robot_feasible"] else f"no: {row['robot_reason']}")
        if row["robot_feasible"]:
            assert cells[3:] == [f"{row['planning_s']:.1f}", f"{row['path_length_m']:.2f}",
                                 str(row["waypoints"]), f"{100 * row['clearance_m']:.1f}",
                                 f"{row['replay_penetration_mm']:.1f}",
                                 f"{row['replay_joint_step_rad']:.3f}"]


def test_report_other_starts_and_reachability_quote_the_committed_result():
    others = pd.read_csv(ROOT / "results" / "baselines" / "other_starts.csv")
    block = REPORT.split("Five more starts")[1].split("\n\n")[1]
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in block.splitlines()[2:]]
    assert len(rows) == len(others)
    for cells, (_, row) in zip(rows, others.iterrows(), strict=True):
        assert cells[0] == f"({row.start_x:.3f}, {row.start_y:.3f}, {row.start_z:.3f})"
        assert cells[1] == ("yes" if row.robot_feasible else f"no: {row.robot_reason}")
        if row.robot_feasible:
            assert cells[2:] == [f"{row.planning_s:.1f}", f"{row.path_length_m:.2f}",
                                 str(row.waypoints), f"{100 * row.clearance_m:.1f}"]
    reach = pd.read_csv(ROOT / "results" / "baselines" / "reachability_summary.csv").iloc[0]
    text = " ".join(REPORT.split("**Where the robot can hand over.**")[1].split("\n\n")[0]
                    .split())
    assert f"{int(reach.held):,} of {int(reach.locations):,} locations" in text
    body = pd.read_csv(ROOT / "results" / "baselines" / "reachability_summary.csv").iloc[1]
    assert body.boundary == "body"
    assert f"every {100 * body.step_m:.0f} cm at {int(body.held):,} of {int(body.locations):,}" \
        in text
    assert (f"({reach.held_x:.3f}, {reach.held_y:.3f}, {reach.held_z:.3f}) m, score "
            f"{reach.held_optimum:g}") in text
    assert (f"({reach.optimum_x:.3f}, {reach.optimum_y:.3f}, {reach.optimum_z:.3f}) m, score "
            f"{reach.optimum:g}") in text
    participants = pd.read_csv(ROOT / "results" / "participants" / "participants.csv")
    served = participants.dropna(subset=["robot_held"])
    assert f"{int(served['robot_held'].sum())} of {len(served)}" in text


def test_report_run_times_are_the_committed_manifests():
    import json

    def minutes(part: str) -> float:
        manifest = json.loads((ROOT / "results" / part / "manifest.json").read_text())
        return manifest["wall_time_s"] / 60

    text = " ".join(REPORT.split("**Run-to-run spread.**")[0].split("## The study and its runs")[1]
                    .split())
    runs = pd.read_csv(ROOT / "results" / "learning" / "runs.csv")
    searches = pd.read_csv(ROOT / "results" / "personalise" / "runs.csv")
    population = json.loads((ROOT / "results" / "population" / "manifest.json").read_text())
    swept = population["workers_computed"] + population["workers_reused"]
    seconds = json.loads((ROOT / "results" / "personalise" / "manifest.json").read_text())[
        "searcher_seconds"]
    # One search run per target, agent and run (read at every budget), and the full runs.
    learned = len(runs.drop_duplicates(["target", "agent", "run"])) + len(
        pd.read_csv(ROOT / "results" / "learning" / "full_runs.csv"))
    for quoted in (f"the learning part's {learned:,} runs {minutes('learning'):.1f}",
                   f"the personalisation part's {len(searches):,} runs "
                   f"{minutes('personalise'):.1f} minutes",
                   f"the exact runs take {sum(seconds.values()):,.0f} seconds",
                   f"the robustness part {minutes('robustness'):.1f}",
                   f"the stance part {minutes('stance'):.1f}",
                   f"reachability {minutes('baselines'):.1f}",
                   f"{swept} workers {minutes('population'):.1f}",
                   f"31 variants {minutes('sensitivity'):.1f}",
                   f"the landscape {minutes('landscape'):.1f}"):
        assert quoted in text, quoted
    sweep = json.loads((ROOT / "results" / "landscape" / "manifest.json").read_text())
    assert f"(its 3 mm sweep {sweep['sweep_seconds']:.0f} s)" in text
    total = float(re.search(r"take ([\d.]+)\s+minutes on this 2-core", text).group(1))
    parts = sum(minutes(p) for p in PARTS)
    assert parts <= total <= parts + 1.5  # the parts, plus the figures and the start-up
    readme = " ".join((ROOT / "README.md").read_text().split())
    assert f"`--force` recomputes everything: {total} minutes on this 2-core machine" in readme
    assert total <= 45  # the default study's budget on 2 cores
    assert "within the target of 45" in text and "within the 45-minute target" in readme


def test_each_committed_part_took_at_most_its_declared_budget():
    """Each part's committed wall time is within the budget its registry entry declares."""
    import json

    from ergohandover.study.registry import QUESTIONS

    for question in QUESTIONS:
        took = json.loads((ROOT / "results" / question.name / "manifest.json").read_text())[
            "wall_time_s"]
        assert took <= question.budget_s, (
            f"{question.name} took {took:.0f} s, over its budget of {question.budget_s:.0f} s")
