"""``ergohandover robustness`` end to end: its Monte Carlo agrees with scoring perturbed postures
through ``ergohandover score``, it is deterministic in its seed, and bad input is one line."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ergohandover.cli import main
from ergohandover.ergonomics.posture import POSTURE_COLUMNS
from ergohandover.io.posture_csv import read_postures
from ergohandover.robustness.measured_error import MEASURED_ERROR
from ergohandover.robustness.posture_error import ANGLE_COLUMNS, SCORES, monte_carlo

ROOT = Path(__file__).resolve().parents[1]
BASELINES = ROOT / "results" / "baselines" / "baselines.csv"
TABLE = ["location", "angle_sd_deg", "structure", "score", "nominal", "mean", "mean_se",
         "p_nominal_or_better", "q05", "q95", "draws"]


@pytest.fixture
def one_posture(tmp_path) -> Path:
    """A real posture: the first row of the study's baselines, its posture columns only."""
    path = tmp_path / "one.csv"
    pd.read_csv(BASELINES)[list(POSTURE_COLUMNS)].iloc[:1].to_csv(path, index=False)
    return path


def robustness(tmp_path: Path, *flags: str, name: str = "out.csv") -> pd.DataFrame:
    out = tmp_path / name
    assert main(["robustness", *flags, "--output", str(out)]) == 0
    return pd.read_csv(out)


def test_agrees_with_scoring_perturbed_postures_through_score(tmp_path, one_posture):
    draws = 4000
    posture = pd.read_csv(one_posture)
    rng = np.random.default_rng(20240611)
    copies = posture.loc[np.zeros(draws, int)].reset_index(drop=True)
    for column in ANGLE_COLUMNS:
        copies[column] = np.clip(copies[column] + rng.normal(0.0, 5.0, draws), -180, 180)
    perturbed, scored = tmp_path / "perturbed.csv", tmp_path / "scored.csv"
    copies.to_csv(perturbed, index=False)
    assert main(["score", "--input", str(perturbed), "--output", str(scored)]) == 0
    direct = pd.read_csv(scored)
    table = robustness(tmp_path, "--postures", str(one_posture), "--angle-sd", "5",
                       "--draws", str(draws)).set_index("score")
    assert list(table.reset_index()[TABLE[:4]].itertuples(index=False)) == [
        ("row1", 5.0, "independent", s) for s in SCORES]
    for score in ("paper_postural", "reba", "rula"):
        se_direct = direct[score].std() / np.sqrt(draws)
        se = np.hypot(se_direct, table.loc[score, "mean_se"])
        assert se > 0, score  # the scores do move under 5° errors
        assert abs(direct[score].mean() - table.loc[score, "mean"]) < 4 * se, score


def test_the_same_seed_gives_the_same_bytes_and_another_seed_other_means(tmp_path, one_posture):
    flags = ["--postures", str(one_posture), "--angle-sd", "2", "5", "--draws", "300"]
    robustness(tmp_path, *flags, "--seed", "7", name="a.csv")
    robustness(tmp_path, *flags, "--seed", "7", name="b.csv")
    other = robustness(tmp_path, *flags, "--seed", "8", name="c.csv")
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    first = pd.read_csv(tmp_path / "a.csv")
    assert first["angle_sd_deg"].tolist() == [2.0] * 3 + [5.0] * 3
    assert not np.allclose(first["mean"], other["mean"])
    # Each SD has its own generator: the first SD's results do not depend on the others.
    alone = robustness(tmp_path, "--postures", str(one_posture), "--angle-sd", "2", "7",
                       "--draws", "300", "--seed", "7", name="d.csv")
    pd.testing.assert_frame_equal(alone.iloc[:3], first.iloc[:3])


def test_no_error_gives_the_nominal_scores(tmp_path, one_posture):
    table = robustness(tmp_path, "--postures", str(one_posture), "--angle-sd", "0",
                       "--draws", "50")
    assert (table["mean"] == table["nominal"]).all()
    assert (table["p_nominal_or_better"] == 1).all() and (table["mean_se"] == 0).all()
    assert (table["q05"] == table["nominal"]).all() and (table["q95"] == table["nominal"]).all()


def test_stdout_is_the_csv_and_bilateral_errors_move_both_sides_together(tmp_path, capsys,
                                                                         one_posture):
    frame = pd.read_csv(one_posture)
    for column in frame.columns:  # a symmetric posture, named
        if column.startswith("right_"):
            frame[column] = frame["left_" + column.removeprefix("right_")]
    frame.insert(0, "name", "symmetric")
    frame.to_csv(one_posture, index=False)
    flips = {}
    for structure in ("independent", "bilateral"):
        capsys.readouterr()
        assert main(["robustness", "--postures", str(one_posture), "--draws", "400",
                     "--structure", structure, "--flips", str(tmp_path / "f.csv")]) == 0
        table = pd.read_csv(io.StringIO(capsys.readouterr().out))
        assert list(table.columns) == TABLE and set(table["location"]) == {"symmetric"}
        assert (table["structure"] == structure).all()
        shares = pd.read_csv(tmp_path / "f.csv")
        assert list(shares.columns) == ["location", "angle_sd_deg", "item", "p_flip"]
        flips[structure] = shares.set_index("item")["p_flip"]
    for item in ("paper_left_arm", "rula_left_upper_arm", "reba_left_wrist"):
        pair = [item, item.replace("left", "right")]
        assert flips["bilateral"][pair[0]] == flips["bilateral"][pair[1]], item
    assert any(flips["independent"][i] != flips["independent"][i.replace("left", "right")]
               for i in ("paper_left_arm", "rula_left_upper_arm", "reba_left_wrist"))


def test_points_mark_infeasible_locations_and_never_score_them(tmp_path, capsys):
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0.0,1.0,0.4\n0.0,0.2,0.1\n")
    out, flips, margins = (tmp_path / "new" / n for n in ("t.csv", "f.csv", "m.csv"))
    capsys.readouterr()
    assert main(["robustness", "--points", str(points), "--draws", "100", "--angle-sd", "2",
                 "5", "--workers", "1", "--output", str(out), "--flips", str(flips),
                 "--margins", str(margins)]) == 0
    err = capsys.readouterr().err
    table = pd.read_csv(out)
    assert list(table.columns) == ["location", "x", "y", "z", "feasible", *TABLE[1:]]
    assert table["location"].tolist() == ["row1"] * 6 + ["row2"] * 6
    assert table["feasible"].tolist() == [1] * 6 + [0] * 6
    assert table[["x", "y", "z"]].iloc[-1].tolist() == [0.0, 0.2, 0.1]
    stats = ["nominal", "mean", "mean_se", "p_nominal_or_better", "q05", "q95", "draws"]
    assert table.loc[table["feasible"] == 1, stats].notna().all().all()
    assert table.loc[table["feasible"] == 0, stats].isna().all().all()
    assert set(pd.read_csv(flips)["location"]) == {"row1"}
    found = pd.read_csv(margins)
    assert set(found["location"]) == {"row1"} and len(found) == len(ANGLE_COLUMNS) * len(SCORES)
    # A short summary per location and SD on stderr (the CSV went to the file).
    assert "row1 (angle SD 2 deg): paper_postural" in err and "row2 (angle SD 5 deg): " \
        "infeasible" in err and str(out) in err
    assert not list(out.parent.glob(".*.tmp"))


BAD = {
    "negative SD": (["--postures", "ONE", "--angle-sd", "5", "-1"], "--angle-sd -1: outside 0-45"),
    "SD beyond the bound": (["--postures", "ONE", "--angle-sd", "46"],
                            "--angle-sd 46: outside 0-45"),
    "infinite SD": (["--postures", "ONE", "--angle-sd", "inf"], "--angle-sd inf: not a finite"),
    "no draws": (["--postures", "ONE", "--draws", "0"], "--draws 0: must be >= 1"),
    "both": (["--postures", "ONE", "--points", "ONE"],
             "give exactly one of --points CSV or --postures CSV (got both)"),
    "neither": ([], "give exactly one of --points CSV or --postures CSV (got neither)"),
    "missing": (["--postures", "MISSING"], "--postures MISSING: no such file"),
    "structure": (["--postures", "ONE", "--structure", "paired"], "--structure paired: not one"),
    "points without x": (["--points", "ONE"], "--points ONE is missing required column 'x'"),
    "measured and SD": (["--postures", "ONE", "--measured-error", "--angle-sd", "2"],
                        "--angle-sd cannot be used with --measured-error"),
    "measured and structure": (["--postures", "ONE", "--measured-error", "--structure",
                                "bilateral"], "--structure cannot be used with --measured-error"),
}


def test_the_measured_error_is_the_study_models_draws(tmp_path, one_posture):
    """--measured-error scores with the robustness part's IMU model: the same Monte Carlo as
    the library's for the seed, one row per score, the model named in place of an SD."""
    table = robustness(tmp_path, "--postures", str(one_posture), "--measured-error",
                       "--draws", "500", "--seed", "3")
    assert len(table) == len(SCORES) and table["angle_sd_deg"].isna().all()
    assert set(table["structure"]) == {MEASURED_ERROR.name}
    posture = read_postures(str(one_posture), "test")[1]
    expected = monte_carlo(posture, MEASURED_ERROR, 500, np.random.default_rng(
        np.random.SeedSequence(3).spawn(1)[0]))
    for score in SCORES:
        row = table[table["score"] == score].iloc[0]
        assert row["mean"] == pytest.approx(expected.mean[score][0])
        assert row["nominal"] == expected.nominal[score][0]


@pytest.mark.parametrize("case", list(BAD))
def test_bad_input_is_one_line_naming_the_flag(tmp_path, capsys, one_posture, case):
    argv, message = BAD[case]
    missing = tmp_path / "missing.csv"
    swap = {"ONE": str(one_posture), "MISSING": str(missing)}
    argv = [swap.get(a, a) for a in argv]
    message = message.replace("MISSING", str(missing)).replace("ONE", str(one_posture))
    out = tmp_path / "out" / "table.csv"
    before = sorted(tmp_path.rglob("*"))
    capsys.readouterr()
    assert main(["robustness", *argv, "--output", str(out), "--flips",
                 str(tmp_path / "flips.csv")]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1, captured.err
    assert captured.err.startswith("ergohandover robustness: error: ")
    assert message in captured.err and "Traceback" not in captured.err
    assert sorted(tmp_path.rglob("*")) == before, "a bad input left a file or folder behind"


@pytest.mark.slow
def test_baseline_reports_the_robust_optimum_beside_the_optimised_location(tmp_path, capsys):
    out = tmp_path / "run" / "baselines.csv"
    assert main(["baseline", "--start", "0.028,1.122,1.354", "--step", "0.04",
                 "--robust-sd", "5", "--output", str(out)]) == 0
    printed = capsys.readouterr().out
    table = pd.read_csv(out)
    robust = pd.read_csv(out.with_name("robust.csv"))
    assert list(robust["location"].unique()) == ["nominal optimum", "robust optimum"]
    assert (robust["angle_sd_deg"] == 5.0).all() and (robust["draws"] >= 2000).all()
    optimised = table[table["method"] == "optimised"].iloc[0]
    nominal = robust[(robust["location"] == "nominal optimum")
                     & (robust["score"] == "paper_postural")].iloc[0]
    # The nominal optimum is the table's optimised location, with its error-free score.
    assert nominal[list("xyz")].to_numpy(float) == pytest.approx(
        optimised[list("xyz")].to_numpy(float))
    assert nominal["nominal"] == optimised["paper_postural"]
    assert "under 5 deg of posture error" in printed and "robust optimum (" in printed
    assert main(["baseline", "--robust-sd", "-1", "--output", str(tmp_path / "x.csv")]) == 2
    assert "--robust-sd" in capsys.readouterr().err
