"""The figures' rules for discrete scores (experiments/analysis/common.py): the plot kind of a
panel, integer ticks on integer axes, N in every figure, one wording for shares; and every
figure script run on the committed results, its PNGs read back."""

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
    "fig_learning": {"learning_min_score.png": 9, "learning_evaluations.png": 0,
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
}
# Texts that state a share as its column holds it (targets.csv fraction: of the grid;
# stats.csv feasible_fraction: the feasible points' share of the grid).
SHARES = {"learning_min_score.png": "paper: optimum 4 on 0.981 % of the grid",
          "learning_evaluations.png": "paper: target on 0.981 % of the grid",
          "score_distribution.png": "N = 3,156,901 feasible points (96.8 % of the grid"}
# A share of something "of the ..." names the grid or its feasible points, nothing else.
OTHER_SHARE = re.compile(r"% of the (?!grid|feasible points)")


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


@pytest.mark.parametrize("script", [
    pytest.param(s, marks=pytest.mark.slow) if s == "fig_learning" else s for s in SCRIPTS])
def test_every_figure_states_n_and_draws_integer_ticks_on_integer_axes(script, tmp_path):
    done = render(script, tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    assert {p.name for p in tmp_path.glob("*.png")} == set(SCRIPTS[script])
    for name, integer_axes in SCRIPTS[script].items():
        text = Image.open(tmp_path / name).text
        assert common.N_PATTERN.search(text["Description"]), f"{name} states no N"
        assert not OTHER_SHARE.search(text["Description"]), f"{name}: a share of what?"
        assert SHARES.get(name, "") in text["Description"]
        ticks = json.loads(text["Comment"])["integer_ticks"]
        assert len(ticks) >= integer_axes, f"{name}: {sorted(ticks)}"
        for axis, locations in ticks.items():
            assert locations, f"{name} {axis}: no tick"
            assert all(t == round(t) for t in locations), f"{name} {axis}: {locations}"


@pytest.mark.slow
@pytest.mark.parametrize("script", ["fig_population", "fig_baselines"])
def test_a_rerun_writes_the_same_bytes(script, tmp_path):
    # population_penalties jitters; baselines_boxplot dodges: both seeded or fixed.
    for folder in ("a", "b"):
        assert render(script, tmp_path / folder).returncode == 0
    for path in (tmp_path / "a").glob("*.png"):
        assert path.read_bytes() == (tmp_path / "b" / path.name).read_bytes(), path.name
