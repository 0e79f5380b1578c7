"""``ergohandover train``: results and report on a landscape, an online run, one-line errors,
and the learning benchmark's smoke run."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from synthetic import bowl_landscape

from ergohandover.cli import main

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def bowl_file(tmp_path) -> Path:
    return bowl_landscape().save(tmp_path / "bowl.npz")


def test_train_on_a_landscape_writes_results_and_reports_the_minimum(bowl_file, tmp_path,
                                                                     capsys):
    out = tmp_path / "run"
    assert main(["train", "--agent", "qlearning", "--steps", "20000", "--seed", "3",
                 "--episode-end", "paper", "--landscape", str(bowl_file),
                 "--output", str(out)]) == 0
    stdout = capsys.readouterr().out
    assert "best paper_postural 5 at (x, y, z) = (0.000, 1.090, 0.390) m" in stdout
    assert "landscape minimum paper_postural 5 at 1 locations" in stdout and ": reached" in stdout
    assert "target paper_postural <= 4 was never reached" in stdout
    trace = pd.read_csv(out / "trace.csv")
    assert trace["best_score"].iloc[-1] == 5 and trace["step"].iloc[-1] == 20_000
    assert pd.read_csv(out / "best_locations.csv")["score"].tolist() == [5]
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["config"]["seed"] == 3 and manifest["config"]["landscape_key"] == "bowl"
    assert manifest["summary"]["reached_global_minimum"] is True
    assert (out / "q_table.npz").exists()


@pytest.mark.parametrize("agent", ["randomwalk", "random-draws", "hillclimb"])
def test_baselines_run_through_the_same_command(bowl_file, tmp_path, agent):
    out = tmp_path / agent
    assert main(["train", "--agent", agent, "--steps", "20000", "--landscape", str(bowl_file),
                 "--output", str(out), "--target", "5"]) == 0
    assert pd.read_csv(out / "trace.csv")["best_score"].min() == 5


def test_train_online_on_a_small_grid_then_from_the_cached_landscape(tmp_path, capsys,
                                                                       monkeypatch):
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "cache"))  # empty
    args = ["train", "--agent", "hillclimb", "--steps", "60", "--boundary",
            "-0.10,0.10,1.0,1.2,0.35,0.5", "--step", "0.05", "--output"]
    assert main([*args, str(tmp_path / "online")]) == 0
    stdout = capsys.readouterr().out
    assert "hillclimb seed 0: best paper_postural" in stdout and "landscape" not in stdout
    online = json.loads((tmp_path / "online" / "manifest.json").read_text())
    assert online["config"]["boundary"].startswith("-0.10")
    assert online["summary"]["steps"] == 60 and "evaluator" in online["config"]
    # Once the grid is swept, the same command reads the landscape cache: same numbers.
    assert main(["sweep", "--boundary", "-0.10,0.10,1.0,1.2,0.35,0.5", "--step", "0.05",
                 "--output", str(tmp_path / "sweep"), "--workers", "1"]) == 0
    capsys.readouterr()
    assert main([*args, str(tmp_path / "cached")]) == 0
    assert "landscape minimum paper_postural" in capsys.readouterr().out
    cached = json.loads((tmp_path / "cached" / "manifest.json").read_text())
    assert cached["config"]["landscape"].startswith(str(tmp_path / "cache"))
    for name in ("trace.csv", "best_locations.csv"):
        a, b = (pd.read_csv(tmp_path / run / name) for run in ("online", "cached"))
        pd.testing.assert_frame_equal(a.drop(columns="time_s", errors="ignore"),
                                      b.drop(columns="time_s", errors="ignore"))


@pytest.mark.parametrize(("args", "message"), [
    (["--agent", "qlearning"], "give exactly one of --time-cap S or --steps N (got neither)"),
    (["--agent", "qlearning", "--steps", "5", "--time-cap", "1"], "(got both)"),
    (["--agent", "qlearning", "--steps", "5", "--seed", "-1"],
     "--seed -1: must be >= 0"),
    (["--agent", "qlearning", "--steps", "1.5"], "--steps 1.5: not a whole number"),
    (["--agent", "qlearning", "--time-cap", "0"], "--time-cap 0: must be > 0 s"),
    (["--agent", "sarsa", "--steps", "5"],
     "--agent sarsa: not one of qlearning, qlearning+prior, qlearning-adaptive, dqn"),
    (["--agent", "pairwise", "--steps", "10"],
     "--agent pairwise: it is told which of two handovers was better, not scores"),
    (["--agent", "random-draws", "--steps", "5", "--temperature", "adaptive"],
     "--temperature adaptive cannot be used with --agent random-draws"),
    (["--agent", "qlearning", "--steps", "5", "--objective", "owas"],
     "--objective owas: not one of paper_postural, reba, reba_ab, rula"),
    (["--agent", "qlearning", "--steps", "5", "--landscape", "missing.npz"],
     "--landscape missing.npz: no such file"),
    (["--agent", "qlearning", "--steps", "5", "--landscape", "BOWL", "--step", "0.01"],
     "--step cannot be used with --landscape"),
    (["--agent", "qlearning", "--steps", "5", "--landscape", "BOWL", "--gaze", "off"],
     "--gaze cannot be used with --landscape"),
    (["--agent", "qlearning", "--steps", "5", "--landscape", "CORRUPT"],
     ": not a readable landscape"),
])
def test_bad_arguments_exit_2_with_one_line_and_write_nothing(bowl_file, tmp_path, capsys,
                                                              args, message):
    corrupt = tmp_path / "corrupt.npz"
    corrupt.write_bytes(bowl_file.read_bytes()[:200])
    args = [str(bowl_file) if a == "BOWL" else str(corrupt) if a == "CORRUPT" else a
            for a in args]
    out = tmp_path / "out"
    assert main(["train", *args, "--output", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ergohandover train: error: ") and message in err
    assert err.count("\n") == 1 and not out.exists()


def test_an_output_that_is_a_file_is_refused_before_the_run(bowl_file, capsys):
    assert main(["train", "--agent", "random-draws", "--steps", "5", "--landscape", str(bowl_file),
                 "--output", str(bowl_file)]) == 2
    assert f"--output {bowl_file}: a file, not a folder" in capsys.readouterr().err


@pytest.mark.smoke
def test_the_learning_benchmark_runs_on_a_tiny_budget(bowl_file):
    result = subprocess.run(
        [sys.executable, str(ROOT / "experiments" / "bench_learning.py"), "--landscape",
         str(bowl_file), "--seeds", "2", "--time-cap", "2", "--rate-steps", "20000",
         "--online-steps", "0", "--agents", "qlearning,random-draws,hillclimb"],
        capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "qlearning" in result.stdout and "steps/s" in result.stdout
    assert "2/2" in result.stdout  # every seed reached the minimum
