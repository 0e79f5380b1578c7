"""The figures' rules for discrete scores (experiments/analysis/common.py): the plot kind of a
panel, integer ticks on integer axes, N in every figure, one wording for shares; and every
figure script run on the committed results, its PNGs read back: N stated, words a reader knows
instead of the results' keys, no two panels drawing the same data, and the figures a reader
could misread (workers out of order, curves ending unannounced) checked against results/."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
from PIL import Image

ROOT = Path(__file__).resolve().parents[1]
ANALYSIS = ROOT / "experiments" / "analysis"
RESULTS = ROOT / "results"
sys.path.insert(0, str(ANALYSIS))

import common  # noqa: E402

# What each script writes from the committed results, and how many of each figure's axes hold
# integers (scores, penalties, run counts) at least.
SCRIPTS = {
    "fig_learning": {"learning_min_score.png": 7, "learning_evaluations.png": 0,
                     "learning_success.png": 0, "learning_best_so_far.png": 8,
                     "learning_rollouts.png": 0},
    "fig_baselines": {"baselines_boxplot.png": 3, "baselines_renders.png": 0,
                      "robot_reachability.png": 0},
    "fig_participants": {"participants.png": 2},
    "fig_population": {"population_penalties.png": 1, "population_proportions.png": 1,
                       "population_optima.png": 0},
    "fig_score_distribution": {"score_distribution.png": 4},
    "fig_sensitivity": {"sensitivity.png": 0},
    "fig_validation": {"validation.png": 0},
    "fig_robustness": {"robustness.png": 1},
    "fig_personalise": {"personalise.png": 0, "personalise_measured.png": 0},
    "fig_capture": {"capture_accuracy.png": 0},
    "fig_people": {"people_angles.png": 0, "people_locations.png": 1},
    "fig_accommodation": {"accommodation.png": 0},
    "fig_shift": {"shift_reference.png": 0, "shift_capacity.png": 0},
}
# Texts that state a share as its column holds it (targets.csv fraction: of the grid;
# stats.csv feasible_fraction: the feasible points' share of the grid).
SHARES = {"learning_min_score.png": "target: paper score 4\non 0.981 % of the grid",
          "learning_evaluations.png": "target: paper score 4\non 0.981 % of the grid",
          "score_distribution.png": "N = 3,156,901 feasible points (96.8 % of the grid"}
# A share of something "of the ..." names the grid or its feasible points, nothing else.
OTHER_SHARE = re.compile(r"% of the (?!grid|feasible points)")
# The results' own keys, which a reader of a figure cannot know: targets, budgets, boundaries,
# workers and any column name (a lower-case word joined by underscores).
INTERNAL = re.compile(r"paper-reward|lexicographic|reba_ab|paper_postural|paper-code|gaze-off"
                      r"|paper-\dmin|\bp\d+-(?:fe)?male\b|\b[a-z]+(?:_[a-z0-9]+)+\b")


def drawn_ticks(ax, axis: str = "y") -> list[float]:
    ax.figure.canvas.draw()
    target = ax.yaxis if axis == "y" else ax.xaxis
    low, high = sorted(target.get_view_interval())
    return [t for t in target.get_majorticklocs() if low - 1e-9 <= t <= high + 1e-9]


# --- the kind of a panel -----------------------------------------------------------------


def test_a_panel_whose_values_are_all_equal_is_counted_not_boxed():
    assert common.plot_kind([4.0] * 10) == "counts"
    assert not common.box_informs([4.0] * 10)


def test_few_score_values_are_counted_even_in_many_runs():
    values = np.repeat([4, 5, 6, 7], 25)
    assert common.plot_kind(values, np.tile(["a", "b"], 50)) == "counts"


def test_a_box_only_where_every_group_has_enough_distinct_values():
    spread = np.arange(20, dtype=float)
    assert common.plot_kind(spread, ["a"] * 10 + ["b"] * 10) == "box"
    # The same values, but one group of three: its box would be its three values.
    assert common.plot_kind(spread[:13], ["a"] * 10 + ["b"] * 3) == "strip"
    assert not common.box_informs([1.0, 2.0, 3.0])
    assert not common.box_informs([1.0, 1.0, 1.0, 2.0, 2.0, 2.0])  # 6 values, 2 levels


def test_plot_kind_rejects_groups_of_another_length():
    with pytest.raises(ValueError, match="group keys"):
        common.plot_kind(np.arange(10.0), ["a"] * 9)


# --- integer axes ------------------------------------------------------------------------


def test_a_constant_integer_panel_gets_integer_ticks_where_matplotlib_alone_gives_fractions():
    fig, (plain, fixed) = plt.subplots(1, 2)
    for ax in (plain, fixed):
        ax.plot(range(5), [4] * 5, "o")
    common.integer_axis(fixed, "y", [4] * 5)
    # The reviewer's panel: matplotlib's own ticks for a constant 4 are 3.96 ... 4.04.
    assert any(t != round(t) for t in drawn_ticks(plain))
    ticks = drawn_ticks(fixed)
    assert ticks and all(t == round(t) for t in ticks) and 4 in ticks
    low, high = fixed.get_ylim()
    assert high - low >= 2  # the constant value does not fill the panel edge to edge
    plt.close(fig)


@pytest.mark.parametrize("values", [[1, 2], [0, 17], [2, 3, 3, 4, 9]])
def test_integer_axis_ticks_are_integers_for_any_range(values):
    fig, ax = plt.subplots()
    ax.plot(range(len(values)), values)
    common.integer_axis(ax, "y", values)
    ticks = drawn_ticks(ax)
    assert ticks and all(t == round(t) for t in ticks)
    assert ax.get_ylim()[0] < min(values) and ax.get_ylim()[1] > max(values)
    plt.close(fig)


def test_is_integral_tells_scores_from_the_lexicographic_objective():
    assert common.is_integral([4.0, 5.0, 7.0])
    assert not common.is_integral([4.0203, 5.0203])
    assert not common.is_integral([])


# --- what keeps a figure from being saved ---------------------------------------------------


def test_problems_finds_a_figure_without_n_and_a_fractional_tick_on_an_integer_axis():
    fig, ax = plt.subplots()
    ax.plot([0, 1], [4, 5])
    common.integer_axis(ax, "y")
    ax.set_title("scores")
    assert common.problems(fig) == ["no 'N = ...' in the figure's title, captions or panel "
                                    "titles"]
    fig.suptitle("scores (N = 10 runs per box)")
    assert common.problems(fig) == []
    ax.set_yticks([4.0, 4.5, 5.0])  # a fixed locator replaces the integer one
    fig.canvas.draw()
    assert any("integer axis" in p for p in common.problems(fig))
    plt.close(fig)


def test_n_in_a_caption_counts_and_n_text_states_unequal_groups():
    fig, _ = plt.subplots()
    common.caption(fig, "Each dot a run; N = 5 start points.")
    assert common.problems(fig) == []
    plt.close(fig)
    assert common.n_text([10, 10], "runs per bar") == "N = 10 runs per bar"
    assert common.n_text([8, 10], "runs per bar") == "N = 8–10 runs per bar"


def test_save_refuses_a_figure_without_n_and_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.setattr(common, "FIGURES", tmp_path)
    fig, ax = plt.subplots()
    ax.set_title("no count here")
    with pytest.raises(ValueError, match="N = "):
        common.save(fig, "bad.png")
    assert not list(tmp_path.iterdir())


def test_save_writes_the_texts_and_integer_ticks_into_the_png(tmp_path, monkeypatch):
    monkeypatch.setattr(common, "FIGURES", tmp_path)
    fig, ax = plt.subplots()
    ax.plot([0, 1], [4, 4])
    common.integer_axis(ax, "y", [4, 4])
    ax.set_title("paper (N = 10 runs)")
    text = Image.open(common.save(fig, "ok.png")).text
    assert "N = 10 runs" in text["Description"]
    (ticks,) = json.loads(text["Comment"])["integer_ticks"].values()
    assert 4.0 in ticks and all(t == round(t) for t in ticks)


def test_save_writes_each_panels_words_and_a_fingerprint_of_its_data(tmp_path, monkeypatch):
    monkeypatch.setattr(common, "FIGURES", tmp_path)
    fig, axes = plt.subplots(1, 3)
    for ax, values in zip(axes, ([1, 2, 3], [1, 2, 3], [1, 2, 4]), strict=True):
        ax.plot([0, 1, 2], values, label="a line")
        ax.set_xlabel("stature [m]")
        ax.legend()
    fig.legend(["figure-wide"])
    fig.suptitle("N = 3 panels")
    comment = json.loads(Image.open(common.save(fig, "panels.png")).text["Comment"])
    panels = comment["panels"]
    assert [p["xlabel"] for p in panels] == ["stature [m]"] * 3
    assert all(p["legend"] == ["a line"] for p in panels)
    assert comment["legends"] == [["figure-wide"]]
    # The same data draw the same fingerprint, other data another.
    assert panels[0]["data"] == panels[1]["data"] != panels[2]["data"]


def test_panel_data_is_none_for_a_panel_that_draws_nothing():
    fig, (empty, full) = plt.subplots(1, 2)
    empty.set_title("words only")
    full.bar([1, 2], [3, 4])
    assert common.panel_data(empty) is None and common.panel_data(full) is not None
    plt.close(fig)


@pytest.mark.parametrize(("key", "words"), [
    ("p5-female", "5th-percentile woman"), ("p50-male", "50th-percentile man"),
    ("p95-female", "95th-percentile woman"), ("p1-male", "1st-percentile man"),
    ("p12-male", "12th-percentile man"), ("reference", "reference")])
def test_worker_words(key, words):
    assert common.worker_words(key) == words


def test_the_reader_words_pass_the_internal_name_check_and_the_keys_fail_it():
    for words in [*common.SCORE_WORDS.values(), common.REBA_AB_NOTE, "5th-percentile woman"]:
        assert not INTERNAL.search(words), words
    for key in ["paper-reward", "reba_ab", "paper_postural", "p5-female", "paper-2min",
                "hamstring_stiffness", "boundary 'paper-code'"]:
        assert INTERNAL.search(key), key


# --- one wording for shares ----------------------------------------------------------------


def test_share_wording_follows_what_each_column_holds():
    stats = pd.read_csv(RESULTS / "landscape" / "stats.csv")
    targets = pd.read_csv(RESULTS / "learning" / "targets.csv")
    dist = pd.read_csv(RESULTS / "landscape" / "distribution.csv")
    # stats.csv: fraction_at_min of the feasible points; feasible_fraction of the grid.
    np.testing.assert_allclose(stats["fraction_at_min"], stats["n_at_min"] / stats["feasible"])
    np.testing.assert_allclose(stats["feasible_fraction"], stats["feasible"] / stats["points"])
    # targets.csv: fraction of the grid (every cell, infeasible ones included).
    np.testing.assert_allclose(targets["fraction"], targets["cells"] / targets["grid_cells"])
    # distribution.csv: fraction of the feasible points.
    feasible = stats.set_index("score")["feasible"]
    np.testing.assert_allclose(dist["fraction"], dist["count"] / dist["score"].map(feasible))
    paper = targets.set_index("target").loc["paper", "fraction"]
    assert common.share_of_grid(paper) == "0.981 % of the grid"
    at_min = stats.set_index("score").loc["paper_postural", "fraction_at_min"]
    assert common.share_of_feasible(at_min, 2) == "1 % of the feasible points"
    assert common.percent(8.001976886856953e-05) == "0.008 %"
    assert common.percent(0.3157975579560805) == "31.6 %"


# --- the scripts on the committed results -----------------------------------------------------


def render(script: str, folder: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "ERGOHANDOVER_RESULTS": str(RESULTS),
           "ERGOHANDOVER_FIGURES": str(folder), "MPLBACKEND": "Agg"}
    return subprocess.run([sys.executable, str(ANALYSIS / f"{script}.py")], env=env,
                          capture_output=True, text=True, timeout=300, cwd=ANALYSIS)


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    """Each script run once on the committed results for all the tests of this module: its
    folder of PNGs."""
    folders: dict[str, Path] = {}

    def folder(script: str) -> Path:
        if script not in folders:
            path = tmp_path_factory.mktemp(script)
            done = render(script, path)
            assert done.returncode == 0, done.stderr[-2000:]
            folders[script] = path
        return folders[script]

    return folder


def slow_learning(scripts):
    """The scripts as parameters, the learning figures' (the slowest) marked slow."""
    return [pytest.param(s, marks=pytest.mark.slow) if s == "fig_learning" else s
            for s in scripts]


def metadata(path: Path) -> tuple[str, dict]:
    """A written figure's texts (title, captions, panel titles) and its panels and legends."""
    text = Image.open(path).text
    return text["Description"], json.loads(text["Comment"])


def every_text(path: Path) -> list[str]:
    """Everything a reader of the figure reads: titles, captions, axis and tick labels,
    legends and texts in the panels."""
    description, comment = metadata(path)
    texts = [description]
    for panel in comment["panels"]:
        texts += [panel["title"], panel["xlabel"], panel["ylabel"], *panel["xticks"],
                  *panel["yticks"], *panel["legend"], *panel["texts"]]
    for legend in comment["legends"]:
        texts += legend
    return texts


@pytest.mark.parametrize("script", slow_learning(SCRIPTS))
@pytest.mark.slow
def test_every_figure_states_n_and_draws_integer_ticks_on_integer_axes(script, rendered):
    folder = rendered(script)
    assert {p.name for p in folder.glob("*.png")} == set(SCRIPTS[script])
    for name, integer_axes in SCRIPTS[script].items():
        text = Image.open(folder / name).text
        assert common.N_PATTERN.search(text["Description"]), f"{name} states no N"
        assert not OTHER_SHARE.search(text["Description"]), f"{name}: a share of what?"
        assert SHARES.get(name, "") in text["Description"]
        ticks = json.loads(text["Comment"])["integer_ticks"]
        assert len(ticks) >= integer_axes, f"{name}: {sorted(ticks)}"
        for axis, locations in ticks.items():
            assert locations, f"{name} {axis}: no tick"
            assert all(t == round(t) for t in locations), f"{name} {axis}: {locations}"


@pytest.mark.parametrize("script", slow_learning(SCRIPTS))
@pytest.mark.slow
def test_no_figure_names_anything_by_the_results_keys(script, rendered):
    # "paper-reward", "lexicographic", "reba_ab", "p5-female": a reader has the figure, not
    # targets.csv; every title, label, tick, legend and caption is in words.
    for name in SCRIPTS[script]:
        found = {m.group(0) for t in every_text(rendered(script) / name)
                 for m in INTERNAL.finditer(t)}
        assert not found, f"{name}: {sorted(found)}"


@pytest.mark.parametrize("script", slow_learning(SCRIPTS))
@pytest.mark.slow
def test_no_two_panels_of_a_figure_draw_the_same_data(script, rendered):
    for name in SCRIPTS[script]:
        _, comment = metadata(rendered(script) / name)
        drawn = [p["data"] for p in comment["panels"] if p["data"]]
        assert drawn, f"{name}: no panel draws data"
        repeated = {d for d in drawn if drawn.count(d) > 1}
        titles = [p["title"] for p in comment["panels"] if p["data"] in repeated]
        assert not repeated, f"{name}: panels with the same data: {titles}"


@pytest.mark.slow
def test_participants_are_ordered_by_stature_smallest_first(rendered):
    table = pd.read_csv(RESULTS / "participants" / "participants.csv")
    statures = table.groupby("worker")["stature_m"].first().sort_values()
    _, comment = metadata(rendered("fig_participants") / "participants.png")
    panels = [p for p in comment["panels"] if p["xticks"]]
    assert len(panels) == 2
    for panel in panels:
        shown = [float(re.search(r"(\d\.\d+) m", t)[1]) for t in panel["xticks"]]
        assert shown == [round(s, 2) for s in statures], panel["xticks"]
        words = [common.worker_words(w).rsplit(" ", 1) for w in statures.index]
        for tick, (percentile, sex) in zip(panel["xticks"], words, strict=True):
            assert sex in tick and percentile.replace("-", " ") in tick, tick


@pytest.mark.slow
def test_population_draws_one_panel_per_one_size_location(rendered):
    one_size = pd.read_csv(RESULTS / "population" / "one_size.csv")
    places = one_size[one_size["objective"] == "paper_postural"][["x", "y", "z"]]
    for name in ("population_penalties.png", "population_proportions.png"):
        _, comment = metadata(rendered("fig_population") / name)
        assert len(comment["panels"]) == len(places.drop_duplicates()), name


@pytest.mark.slow
def test_learning_curves_that_end_early_say_where(rendered):
    curves = pd.read_csv(RESULTS / "learning" / "curves.csv")
    ends = curves.groupby("agent")["evaluations"].max()
    early = ends[ends < ends.max()]
    assert len(early)  # DQN, to the paper's 5-minute cap: the case this test is for
    sys.path.insert(0, str(ANALYSIS))
    from learning_tables import AGENT_NAMES

    for name in ("learning_success.png", "learning_best_so_far.png"):
        texts = every_text(rendered("fig_learning") / name)
        caption = " ".join(texts[0].split())  # captions are wrapped: lines joined
        assert f"Every curve runs to {int(ends.max()):,} evaluations" in caption, name
        for agent, end in early.items():
            assert f"{AGENT_NAMES[agent]}'s at {int(end):,}" in caption, (name, agent)
            assert any(f"{AGENT_NAMES[agent]} ends:\nits budget, {int(end):,}" in t
                       for t in texts), (name, agent)
        _, comment = metadata(rendered("fig_learning") / name)
        # One legend for the figure, naming every agent: no panel's lines go unnamed.
        (legend,) = comment["legends"]
        assert {AGENT_NAMES[a] for a in ends.index} <= set(legend), legend


@pytest.mark.slow
def test_learning_panels_name_their_target_in_words(rendered):
    targets = pd.read_csv(RESULTS / "learning" / "targets.csv")
    for name in ("learning_success.png", "learning_best_so_far.png",
                 "learning_evaluations.png"):
        _, comment = metadata(rendered("fig_learning") / name)
        titles = [p["title"] for p in comment["panels"] if p["title"]]
        assert len(titles) == len(targets), name
        assert all(t.startswith("target: ") for t in titles), titles
        # The paper's reward (its score plus symmetry) and the tie-broken target say so.
        assert any("nearest the midline" in t for t in titles)
        assert any("with the best tie-breaks" in t for t in titles)


@pytest.mark.slow
def test_personalise_curves_that_stop_at_a_smaller_budget_say_so(rendered):
    curves = pd.read_csv(RESULTS / "personalise" / "curves.csv")
    ends = curves.groupby("searcher")["evaluations"].max()
    early = ends[ends < ends.max()]  # none in the default study: no searcher is capped there
    sys.path.insert(0, str(ANALYSIS))
    from fig_personalise import label

    path = rendered("fig_personalise") / "personalise.png"
    description, comment = metadata(path)
    caption = " ".join(description.split())  # captions are wrapped: lines joined
    notes = [t for p in comment["panels"] for t in p["texts"]]
    for searcher, end in early.items():
        assert f"{label(searcher)} to {int(end):,}" in caption, searcher
        assert any(f"run to\n{int(end):,} only" in t for t in notes), (searcher, notes)
    assert ("run to a smaller budget" in caption) == bool(len(early))
    # Each method's panel pairs its own two curves in one colour: no panel draws two methods.
    titles = [p["title"] for p in comment["panels"]]
    assert len(titles) == len(set(titles))


@pytest.mark.slow
def test_score_distribution_explains_reba_table_a_plus_b(rendered):
    scores = set(pd.read_csv(RESULTS / "landscape" / "distribution.csv")["score"])
    description, comment = metadata(rendered("fig_score_distribution") /
                                    "score_distribution.png")
    titles = [p["title"] for p in comment["panels"]]
    assert titles == [common.SCORE_WORDS[s] for s in
                      dict.fromkeys(pd.read_csv(RESULTS / "landscape" /
                                                "distribution.csv")["score"])]
    if "reba_ab" in scores:
        assert common.REBA_AB_NOTE in " ".join(description.split())


@pytest.mark.slow
def test_reachability_is_one_picture_that_states_how_much_is_held(rendered):
    summary = pd.read_csv(RESULTS / "baselines" / "reachability_summary.csv")
    description, comment = metadata(rendered("fig_baselines") / "robot_reachability.png")
    titled = [p for p in comment["panels"] if p["title"]]
    assert len(titled) == 1  # the colour bar beside it has no title
    held, total = int(summary["held"].sum()), int(summary["locations"].sum())
    verdict = "every location tried" if held == total else f"{held:,} of {total:,}"
    assert verdict in titled[0]["title"] and f"N = {total:,} locations" in titled[0]["title"]
    description = " ".join(description.split())
    for r in summary.itertuples():
        assert f"{int(r.held):,} of {int(r.locations):,}" in description, r.boundary


@pytest.mark.slow
def test_renders_state_our_score_beside_the_papers_in_words(rendered):
    table = pd.read_csv(RESULTS / "baselines" / "baselines.csv")
    texts = every_text(rendered("fig_baselines") / "baselines_renders.png")
    assert not any(re.search(r"postural \d+ \(paper \d+\)", t) for t in texts)
    for r in table.itertuples():
        reported = ("the paper reported the same" if r.paper_postural_paper == r.paper_postural
                    else f"the paper reported {r.paper_postural_paper:g}")
        assert any(t.startswith(f"paper score {r.paper_postural:g} ({reported})")
                   for t in texts), (r.method, reported)


@pytest.mark.slow
@pytest.mark.parametrize("script", ["fig_population", "fig_baselines", "fig_participants",
                                    "fig_personalise", "fig_score_distribution"])
def test_a_rerun_writes_the_same_bytes(script, tmp_path):
    # population_penalties jitters; baselines_boxplot dodges: both seeded or fixed.
    for folder in ("a", "b"):
        assert render(script, tmp_path / folder).returncode == 0
    for path in (tmp_path / "a").glob("*.png"):
        assert path.read_bytes() == (tmp_path / "b" / path.name).read_bytes(), path.name
