"""The workload columns through the command line — ``evaluate``, ``score`` and ``report`` agree
with each other and with the page they print — and their one-line refusals."""

from __future__ import annotations

import html
import re
import shutil

import numpy as np
import pandas as pd
import pytest
from cli_run import run_cli
from PIL import Image

from ergohandover.ergonomics.posture import REQUIRED_COLUMNS
from ergohandover.viewer.report_page import PAGE_COLUMNS
from ergohandover.workload import WORKLOAD_COLUMNS

POINTS = "x,y,z\n0.001,1.005,0.414\n0.0,0.55,0.40\n"


@pytest.fixture(scope="module")
def evaluated(tmp_path_factory):
    folder = tmp_path_factory.mktemp("workload")
    points = folder / "points.csv"
    points.write_text(POINTS)
    out = folder / "evaluation.csv"
    done = run_cli("evaluate", "--points", str(points), "--output", str(out), "--manikin",
                   "f05", "--lift-frequency", "2", "--lift-destination", "0.9")
    assert done.returncode == 0, done.stderr
    return folder, pd.read_csv(out)


def test_evaluate_writes_every_workload_column(evaluated):
    _, table = evaluated
    assert [c for c in table.columns if c in WORKLOAD_COLUMNS] == list(WORKLOAD_COLUMNS)
    assert table["feasible"].tolist() == [1, 1]
    # Bending to the low location loads the back more and lifts farther to 0.9 m.
    assert table["back_compression_n"].iloc[1] > table["back_compression_n"].iloc[0]
    assert table["niosh_d_cm"].tolist() == pytest.approx([10.5, 35.0])
    assert table["niosh_dm"].iloc[0] == pytest.approx(1.0)  # D counts as at least 25 cm
    assert table["owas"].between(1, 4).all()


def test_scoring_the_evaluation_gives_its_workload_again(evaluated, tmp_path):
    folder, table = evaluated
    out = tmp_path / "scores.csv"
    done = run_cli("score", "--input", str(folder / "evaluation.csv"), "--output", str(out),
                   "--manikin", "f05", "--lift-frequency", "2", "--lift-destination", "0.9")
    assert done.returncode == 0, done.stderr
    scored = pd.read_csv(out)
    for column in WORKLOAD_COLUMNS:
        assert np.allclose(scored[column], table[column], rtol=1e-9), column
    # Another body weighs the same posture differently; the lift and OWAS do not change.
    other = tmp_path / "m95.csv"
    assert run_cli("score", "--input", str(folder / "evaluation.csv"), "--output", str(other),
                   "--manikin", "m95", "--lift-frequency", "2",
                   "--lift-destination", "0.9").returncode == 0
    heavier = pd.read_csv(other)
    assert (heavier["back_compression_n"] > scored["back_compression_n"]).all()
    assert heavier["niosh_li"].tolist() == pytest.approx(scored["niosh_li"].tolist())


@pytest.mark.parametrize("args, message", [
    (["--lift-frequency", "20"], r"--lift-frequency 20: outside 0-15"),
    (["--lift-destination", "-1"], r"--lift-destination -1: outside 0-1.75"),
    (["--lift-duration", "shift"], r"--lift-duration shift"),
    (["--manikin", "f05", "--percentile", "p50-male"], r"--manikin f05 and --percentile"),
    (["--manikin", "f10"], r"--manikin f10"),
    (["--rate", "-1"], r"--rate -1: must be > 0"),
    (["--hold", "0"], r"--hold 0: must be > 0"),
    (["--shift-hours", "30"], r"--shift-hours 30"),
    (["--rate", "10", "--hold", "8"], r"--hold 8 is not allowed with --rate 10: a handover "
                                      r"every 6 s leaves no rest"),
])
def test_bad_task_or_body_flags_exit_2_with_one_line_and_write_nothing(tmp_path, args,
                                                                       message):
    points = tmp_path / "points.csv"
    points.write_text(POINTS)
    out = tmp_path / "out.csv"
    done = run_cli("evaluate", "--points", str(points), "--output", str(out), *args)
    assert done.returncode == 2
    assert len(done.stderr.strip().splitlines()) == 1 and re.search(message, done.stderr)
    assert not out.exists()


def test_a_location_below_the_floor_is_refused_before_scoring(tmp_path):
    rows = tmp_path / "postures.csv"
    table = pd.DataFrame(0.0, index=range(2), columns=list(REQUIRED_COLUMNS))
    table[["x", "y", "z"]] = [[0.0, 1.0, 0.4], [0.0, -0.2, 0.4]]
    table.to_csv(rows, index=False)
    done = run_cli("score", "--input", str(rows), "--output", str(tmp_path / "s.csv"))
    assert done.returncode == 2, done.stderr
    assert "row 2, column 'y': -0.2 is not allowed" in done.stderr
    assert not (tmp_path / "s.csv").exists()


def test_a_shift_is_the_same_through_evaluate_and_score_and_a_harder_one_keeps_less(
        evaluated, tmp_path):
    from ergohandover.workload.strength import JOINTS

    folder, table = evaluated
    shift = [c for c in table.columns if c.endswith(("_load_share", "_capacity_end",
                                                     "_failure_min")) or c.startswith("lifft")]
    assert len(shift) == 3 * len(JOINTS) + 4
    harder = tmp_path / "harder.csv"
    assert run_cli("evaluate", "--points", str(folder / "points.csv"), "--output", str(harder),
                   "--manikin", "f05", "--rate", "6", "--hold", "8").returncode == 0
    harder = pd.read_csv(harder)
    # The load is the posture's: the same at any rate; what it leaves is less.
    assert np.allclose(harder["shoulder_load_share"], table["shoulder_load_share"])
    kept = harder["shift_capacity_end"].fillna(0.0)
    assert (kept <= table["shift_capacity_end"]).all() and (kept < table[
        "shift_capacity_end"]).any()
    assert (harder["lifft_dose"] > table["lifft_dose"]).all()  # more handovers in the day
    scored = tmp_path / "scored.csv"
    assert run_cli("score", "--input", str(folder / "evaluation.csv"), "--output", str(scored),
                   "--manikin", "f05", "--rate", "6", "--hold", "8").returncode == 0
    scored = pd.read_csv(scored)
    for column in shift:
        assert np.allclose(scored[column], harder[column], rtol=1e-9, equal_nan=True), column


def test_workload_flags_need_the_posture_columns():
    done = run_cli("score", "--items", "-", "--manikin", "f05", stdin="reba_trunk\n1\n")
    assert done.returncode == 2 and "--manikin cannot be used with --items" in done.stderr
    done = run_cli("score", "--items", "-", "--rate", "4", stdin="reba_trunk\n1\n")
    assert done.returncode == 2 and "--rate cannot be used with --items" in done.stderr


def page_values(html: str) -> list[dict[str, str]]:
    """Each page's shown values by column, read back from the HTML."""
    pages = html.split("break-after: page")
    return [dict(re.findall(r'data-column="([a-z0-9_]+)">([^<]*)<', page)) for page in pages]


@pytest.fixture(scope="module")
def reported(tmp_path_factory):
    folder = tmp_path_factory.mktemp("report")
    done = run_cli("report", "--location", "0.001,1.005,0.414", "--location", "0,0.55,0.4",
                   "--manikin", "m95", "--output", str(folder / "out"))
    assert done.returncode == 0, done.stderr
    return folder / "out"


def test_the_reports_numbers_are_its_csvs(reported):
    text = pd.read_csv(reported / "report.csv", dtype=str, keep_default_na=False)
    pages = page_values((reported / "report.html").read_text())
    assert len(pages) == len(text) == 2
    for page, (_, row) in zip(pages, text.iterrows(), strict=True):
        assert set(page) <= set(PAGE_COLUMNS) and {"reba", "rula", "owas", "niosh_li"} <= set(page)
        for column, value in page.items():
            assert value == row[column], column
    assert sorted(p.name for p in reported.glob("*.png")) == ["location_01.png",
                                                               "location_02.png"]


def test_the_report_agrees_with_evaluate(reported, tmp_path):
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0.001,1.005,0.414\n0,0.55,0.4\n")
    assert run_cli("evaluate", "--points", str(points), "--output", str(tmp_path / "e.csv"),
                   "--manikin", "m95").returncode == 0
    evaluation = pd.read_csv(tmp_path / "e.csv")
    text = pd.read_csv(reported / "report.csv")
    for column in ("reba", "rula", "owas", "paper_postural"):
        assert text[column].tolist() == evaluation[column].tolist()
    assert text["shift_capacity_end"].tolist() == evaluation["shift_capacity_end"].round(
        3).tolist()
    assert text["niosh_li"].tolist() == evaluation["niosh_li"].round(2).tolist()
    assert text["back_compression_n"].tolist() == evaluation["back_compression_n"].round(
        0).tolist()


@pytest.mark.skipif(shutil.which("chromium") is None, reason="needs Debian's chromium")
def test_the_report_renders_in_chromium_and_prints_to_pdf(reported, tmp_path):
    from ergohandover.viewer.chromium import print_pdf, screenshot

    png = screenshot(reported / "report.html", tmp_path / "page.png")
    image = Image.open(png).convert("RGB")
    # The page drew its picture and tables: many colours, and dark text on the white sheet.
    assert len(image.getcolors(maxcolors=1 << 20)) > 200
    assert np.asarray(image).min() < 60
    pdf = print_pdf(reported / "report.html", tmp_path / "page.pdf")
    assert pdf.read_bytes().startswith(b"%PDF") and pdf.stat().st_size > 20_000


def test_a_location_beyond_the_workforce_grid_says_why_it_has_no_share(reported, tmp_path):
    done = run_cli("report", "--location", "0,0.3,0.65", "--output", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    page = (tmp_path / "out" / "report.html").read_text()
    text = pd.read_csv(tmp_path / "out" / "report.csv", dtype=str, keep_default_na=False)
    why = text["workforce_note"].iloc[0]
    assert why.startswith("beyond the study's 3 cm grid of the workforce (its nearest point is ")
    assert text["measured_share"].iloc[0] == ""
    assert html.escape(f"no workforce share: {why}") in page
    assert "data-why" in page and 'data-column="exact_share"' not in page
    # A location the study measured the workforce at has its shares and no note.
    shown = pd.read_csv(reported / "report.csv", dtype=str, keep_default_na=False)
    assert shown["workforce_note"].iloc[0] == "" and shown["measured_share"].iloc[0] != ""
