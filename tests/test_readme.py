"""The README is an honest front door: its test command is the one CI runs, it stays short, its
links lead somewhere, and every number of its headline table is the committed result."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
RESULTS = ROOT / "results"
sys.path.insert(0, str(ROOT / "experiments" / "analysis"))

import headline_rules  # noqa: E402
import learning_tables  # noqa: E402
import people_tables  # noqa: E402
import personalise_tables  # noqa: E402
import population_tables  # noqa: E402
import readme_blocks  # noqa: E402
import robustness_tables  # noqa: E402
import stance_tables  # noqa: E402
import workload_tables  # noqa: E402


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

def headline_rows() -> dict[str, tuple[str, str, str]]:
    """Each row of the headline table, by its label: (label cell, the paper, we measured)."""
    table = README.split("<!-- headline")[1].split("-->", 1)[1].strip("\n").split("\n\n")[0]
    rows = {}
    for line in table.splitlines()[2:]:
        label, paper, ours = (cell.strip() for cell in line.strip().strip("|").split("|"))
        rows[re.match(r"\[(.+?)\]", label).group(1)] = (label, paper, ours)
    return rows


def paper_column() -> dict[str, str]:
    """results/tables.md's landscape table: the paper's cell of each row."""
    text = (RESULTS / "tables.md").read_text().split("## The exhaustive landscape")[1]
    table = text.split("\n\n")[1]
    return {cells[0]: cells[1] for cells in
            ([c.strip() for c in line.strip("|").split("|")] for line in table.splitlines()[2:])}


def span(values) -> str:
    """``4`` or ``2–7``: the range of integer values as the table writes it."""
    low, high = int(min(values)), int(max(values))
    return str(low) if low == high else f"{low}–{high}"


def percentile(worker: str) -> str:
    return re.fullmatch(r"p(\d+)-(?:fe)?male", worker).group(1)


def expected() -> dict[str, tuple[list[str], list[str]]]:
    """Each row's quoted fragments, built from results/: (the paper's, ours)."""
    paper = paper_column()
    stats = pd.read_csv(RESULTS / "landscape" / "stats.csv").set_index("score")
    manifest = json.loads((RESULTS / "landscape" / "manifest.json").read_text())
    distribution = pd.read_csv(RESULTS / "landscape" / "distribution.csv")
    variants = pd.read_csv(RESULTS / "landscape" / "variants.csv")
    sensitivity = pd.read_csv(RESULTS / "sensitivity" / "sensitivity.csv")
    summary = pd.read_csv(RESULTS / "learning" / "summary.csv")
    comparisons = pd.read_csv(RESULTS / "learning" / "comparisons.csv")
    baselines = pd.read_csv(RESULTS / "baselines" / "baselines.csv")
    others = pd.read_csv(RESULTS / "baselines" / "other_starts.csv")
    reach = pd.read_csv(RESULTS / "baselines" / "reachability_summary.csv").iloc[0]
    participants = pd.read_csv(RESULTS / "participants" / "participants.csv")
    workers = pd.read_csv(RESULTS / "population" / "workers.csv")
    one_size = pd.read_csv(RESULTS / "population" / "one_size.csv")
    groups = pd.read_csv(RESULTS / "population" / "groups.csv")
    proportions = pd.read_csv(RESULTS / "population" / "proportions.csv")
    tests = pd.read_csv(RESULTS / "population" / "who_pays_tests.csv")
    held_out = pd.read_csv(RESULTS / "robustness" / "one_size.csv")
    twins = pd.read_csv(RESULTS / "population" / "fixed_ratio_twin.csv")
    rows = {}

    postural = stats.loc["paper_postural"]
    rows["the landscape"] = (
        [f"grid ({paper['grid points']}) takes {paper['time to evaluate all']}"],
        [f"{int(postural['points']):,} locations in {manifest['sweep_seconds'] / 60:.1f} min "
         f"on {manifest['machine']['cpus']} cores"])

    top = distribution[distribution["score"] == "paper_postural"].nlargest(2, "fraction")
    gaze_off = variants[(variants["boundary"] == "paper-code") & (variants["gaze"] == "off")
                        & (variants["score"] == "paper_postural")].iloc[0]
    assert gaze_off["min"] == postural["min"]
    no_effort = sensitivity[sensitivity["variant"].str.startswith("no effort task")].iloc[0]
    rows["its minimum"] = (
        [f"scores {paper['most common postural scores']}",
         f"{paper['share of the grid at the minimum']} reaches the minimum, "
         f"{paper['minimum postural score']}"],
        ["mostly " + " and ".join(f"{int(r.value)} ({100 * r.fraction:.0f} %)"
                                  for r in top.itertuples()),
         f"the minimum is **{int(postural['min'])}**",
         f"on {100 * postural['n_at_min'] / postural['points']:.2f} % of the grid "
         f"({100 * postural['fraction_at_min']:.2f} % of the feasible points)",
         f"({postural['best_x']:.3f}, {postural['best_y']:.3f}, {postural['best_z']:.3f}) m",
         f"on {100 * gaze_off['fraction_at_min']:.1f} % of a {100 * gaze_off['step']:.0f} cm grid",
         f"; {int(no_effort['paper_postural_min'])} when the twin does not feel the load",
         headline_rules.rules(RESULTS)["its minimum"].reverses[1]])

    matched = summary[summary["mapping"] == 315.0]  # the paper's rate: paper-2min, paper-5min
    budgets = list(dict.fromkeys(matched["budget"]))
    # The paper's protocol, as its own configuration reproduces it: runs per wall-clock cap.
    protocol = json.loads((ROOT / "experiments" / "configs" / "paper.json").read_text())
    runs = protocol["learning"]["runs"]
    minutes = [f"{cap / 60:g}" for cap in protocol["learning"]["wall_caps_s"]]
    assert [re.fullmatch(r"paper-(\d+)min", b).group(1) for b in budgets] == minutes
    block = learning_tables.blocks(RESULTS)["learning-claim"]
    rows["learning"] = (
        [f"{runs} Q-learning runs at {minutes[0]} min and {runs} at {minutes[1]} min"],
        [f"<!-- learning-claim -->{block}<!-- /learning-claim -->"])

    block = learning_tables.blocks(RESULTS)["learning-learns"]
    learner = comparisons[comparisons["agent"] == "qlearning"]
    assert learner["mapping"].nunique() == 3 and (learner["n"] >= 100).all()
    rows["does it learn?"] = ([], [f"<!-- learning-learns -->{block}<!-- /learning-learns -->"])

    opt = baselines[baselines["method"] == "optimised"]
    short = baselines[baselines["method"] == "shortest_distance"]
    starts = baselines[["start_x", "start_y", "start_z"]].drop_duplicates()
    assert (opt["paper_postural"].to_numpy() < short["paper_postural"].to_numpy()).all()
    assert len(starts) == 5  # "all five starts"
    rows["optimised vs shortest distance"] = (
        [f"({span(opt['paper_postural_paper'])} vs {span(short['paper_postural_paper'])})"],
        [f"{span(opt['paper_postural'])} vs {span(short['paper_postural'])} from every start",
         f"REBA {span(opt['reba'])} vs {span(short['reba'])}",
         f"RULA {span(opt['rula'])} vs {span(short['rula'])}",
         f"({len(starts)} starts", *headline_rules.rules(RESULTS)[
             "optimised vs shortest distance"].reverses])

    assert baselines["robot_feasible"].all()
    rows["the robot"] = (
        [],
        [f"all {len(baselines)} carries ({len(starts)} starts, "
         f"{baselines['method'].nunique()} locations each)",
         f"{int(others['robot_feasible'].sum())} of {len(others)} more starts",
         f"{int(reach['held']):,} of {int(reach['locations']):,} locations of the grid every "
         f"{100 * reach['step_m']:.0f} cm"])

    sizes = participants.drop_duplicates("worker").sort_values("stature_m")["worker"]
    own = participants[participants["location"] == "own-optimised"]["reba"]
    shortest = participants[participants["location"] == "shortest-distance"]["reba"]
    assert len(sizes) == 6  # "six simulated workers"
    assert sizes.iloc[0].endswith("-female") and sizes.iloc[-1].endswith("-male")
    assert "five VR participants" in (RESULTS / "tables.md").read_text()
    rows["participants"] = (
        [],
        [f"({percentile(sizes.iloc[0])}th-percentile woman to "
         f"{percentile(sizes.iloc[-1])}th-percentile man)",
         f"REBA {span(own)} at their own optimum vs {span(shortest)} at the shortest-distance",
         *headline_rules.rules(RESULTS)["participants"].reverses])

    sampled = workers[workers["reference"] == 0]
    reference = workers.loc[workers["reference"] == 1, "worker"].iloc[0]
    best = one_size[(one_size["objective"] == "paper_postural")
                    & (one_size["choice"] == "mean")].iloc[0]
    held = held_out[(held_out["objective"] == "paper_postural")
                    & (held_out["choice"] == "mean")].iloc[0]
    sex = groups[(groups["objective"] == "paper_postural") & (groups["choice"] == "reference")
                 & (groups["by"] == "sex")].set_index("group")["mean_penalty"]
    male = proportions[(proportions["objective"] == "paper_postural")
                       & (proportions["choice"] == "reference")
                       & (proportions["term"] == "male")].iloc[0]
    planned = population_tables.planned_sex(tests)
    stature = tests[(tests["objective"] == "paper_postural") & (tests["choice"] == "reference")
                    & (tests["question"] == "stature")
                    & (tests["model"] == population_tables.planned_model(tests))].iloc[0]
    shift = twins.pivot(index="objective", columns="proportions", values=["y", "z"])
    moved = 100 * max((shift[(a, "ansur2")] - shift[(a, "drillis-contini")]).abs().max()
                      for a in ("y", "z"))
    rows["population"] = (
        [],
        [f"{len(sampled)} sampled workers ({(sampled['sex'] == 'female').sum()} women)",
         f"costs {held['split_half_held_out']:.2f} points of the postural score on workers it "
         f"was not chosen on (95 % of random splits {held['split_half_held_out_q025']:.2f}–"
         f"{held['split_half_held_out_q975']:.2f}; {best['mean_penalty']:.2f} in sample, where "
         f"it penalises {100 * best['share_penalised']:.0f} % of them)",
         f"at the {percentile(reference)}th-percentile man's optimum women pay "
         f"{sex['female']:.2f}, men {sex['male']:.2f}",
         f"Holm over the {int(planned['family'])} who-pays tests",
         "stature matters (Holm-adjusted p {})".format(
             "< 0.001" if stature["p_holm"] < 0.001 else f"= {stature['p_holm']:.2g}"),
         f"of the same size by {planned['estimate']:+.2f} ({planned['ci_low']:+.2f} to "
         f"{planned['ci_high']:+.2f}; Holm-adjusted p = "
         f"{planned['p_holm']:.2g}; a straight line in stature gave {male['coef']:+.2f}, "
         f"p = {male['p']:.2g} unadjusted)",
         f"moves the optimum by at most {moved:.0f} cm"])

    block = robustness_tables.blocks(RESULTS)["robustness-headline"]
    rows["under error"] = ([], [f"<!-- robustness-headline -->{block}"
                                f"<!-- /robustness-headline -->"])
    block = stance_tables.blocks(RESULTS)["stance-headline"]
    rows["a worker who steps"] = ([], [f"<!-- stance-headline -->{block}"
                                       f"<!-- /stance-headline -->"])
    block = people_tables.blocks(RESULTS)["people-headline"]
    rows["beside people"] = ([], [f"<!-- people-headline -->{block}<!-- /people-headline -->"])
    block = personalise_tables.blocks(RESULTS)["personalise-headline"]
    rows["personalising"] = ([], [f"<!-- personalise-headline -->{block}"
                                  f"<!-- /personalise-headline -->"])
    block = workload_tables.blocks(RESULTS)["accommodation-headline"]
    rows["a workforce's zone"] = ([], [f"<!-- accommodation-headline -->{block}"
                                       f"<!-- /accommodation-headline -->"])
    return rows


def test_every_number_of_the_headline_table_is_the_committed_result():
    rows, want = headline_rows(), expected()
    assert list(rows) == list(want)
    for label, (label_cell, paper, ours) in rows.items():
        assert not re.search(r"\d", label_cell), label
        for cell, fragments in ((paper, want[label][0]), (ours, want[label][1])):
            for fragment in fragments:
                assert fragment in cell, (label, fragment)
                cell = cell.replace(fragment, "")
            # Nothing numeric is left that no fragment checked.
            assert not re.search(r"\d", cell), (label, cell)


def test_the_learning_claim_block_lives_in_the_readme():
    assert readme_blocks.where("learning-claim") == ROOT / "README.md"
