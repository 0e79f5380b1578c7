"""``ergohandover personalise`` with its default searcher, the fitted twin, answered with
measured angles (an IMU's Posture CSV rows, a camera's keypoint frames) or with scores alone;
a session stopped with Ctrl-C resumes to the same model."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from cli_run import run_cli, wait_for
from test_cli_capture import frame_answer

from ergohandover.cli import personalise as command

ROOT = Path(__file__).resolve().parents[1]
SMALL = ["--boundary", "-0.1,0.1,1.0,1.2,0.35,0.5", "--step", "0.05"]  # 5 x 5 x 4 cells
WORKER = ["--stature", "1.756", "--sex", "male"]
MODEL_LINES = ("fitted twin:", "its model recommends", "it expects")


def history(output: Path) -> list[dict]:
    return json.loads((output / "state.json").read_text())["history"]


def model_lines(text: str) -> list[str]:
    """What the fitted twin's model said at the end of a session."""
    return [line for line in text.splitlines() if line.startswith(MODEL_LINES)]


def posture_answers() -> tuple[list[str], list[str]]:
    """A header line, then three Posture CSV rows of examples/postures.csv (as an IMU suit's
    program would send them)."""
    table = pd.read_csv(ROOT / "examples" / "postures.csv").drop(columns="name")
    rows = [",".join(f"{v:g}" for v in row) for row in table.head(3).to_numpy()]
    return [",".join(table.columns)], rows


def test_the_default_searcher_is_the_fitted_twin_and_without_a_prior_it_asks_for_another():
    assert command.DEFAULT_SEARCHER == "fitted-twin"
    done = run_cli("personalise", "--oracle", "ask", "--no-prior", *WORKER, *SMALL)
    assert done.returncode == 2 and done.stderr.count("\n") == 1
    assert "--no-prior: the default searcher, fitted-twin, starts from the prior" in done.stderr


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["posture rows", "keypoint frames"])
def test_an_angle_session_stopped_with_ctrl_c_resumes_to_the_same_model(tmp_path, kind):
    if kind == "posture rows":
        first, answers = posture_answers()
        flags: list[str] = []
    else:
        first, answers = [], [",".join(frame_answer("zed34", n)) for n in (1, 2, 1)]
        flags = ["--answer-format", "keypoints:zed34"]
    argv = [sys.executable, "-m", "ergohandover.cli", "personalise", "--oracle", "ask",
            *WORKER, *SMALL, "--trials", "3", *flags]
    whole = subprocess.run([*argv, "--output", str(tmp_path / "whole")],
                           input="".join(f"{a}\n" for a in [*first, *answers]),
                           capture_output=True, text=True, timeout=900)
    assert whole.returncode == 0, whole.stderr
    out = tmp_path / "run"
    stopped = subprocess.Popen([*argv, "--output", str(out)], stdin=subprocess.PIPE,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        stopped.stdin.write("".join(f"{a}\n" for a in [*first, *answers[:2]]))
        stopped.stdin.flush()
        wait_for(lambda: (out / "state.json").exists() and len(history(out)) == 2,
                 "two saved answers", timeout=600)
        stopped.send_signal(signal.SIGINT)
        _, err = stopped.communicate(timeout=120)
    finally:
        if stopped.poll() is None:
            stopped.kill()
    assert stopped.returncode == 130
    assert err.strip().splitlines()[-1].endswith("rerun the same command to resume")
    # Every answer kept the angles it carried, which the resumed model is told again.
    assert all(h["posture"] for h in history(out))
    again = subprocess.run([*argv, "--output", str(out)], input=f"{answers[2]}\n",
                           capture_output=True, text=True, timeout=900)
    assert again.returncode == 0, again.stderr
    said = model_lines(again.stdout)
    assert len(said) == 3 and said == model_lines(whole.stdout)
    assert "probability that it is this worker's optimum" in said[1]
    assert "at the prior's location (no search): a gain of" in said[2]


@pytest.mark.slow
def test_the_fitted_twin_learns_from_scores_alone(tmp_path):
    done = run_cli("personalise", "--oracle", "ask", *WORKER, *SMALL, "--trials", "3",
                   "--output", str(tmp_path / "s"), stdin="4\n5\n4\n")
    assert done.returncode == 0, done.stderr
    assert len(model_lines(done.stdout)) == 3
    assert [h.get("posture") for h in history(tmp_path / "s")] == [None, None, None]


def test_an_imu_suits_angles_weigh_the_fitted_twin_and_a_session_keeps_its_instrument(tmp_path):
    output = tmp_path / "imu"
    done = run_cli("personalise", "--oracle", "twin", *WORKER, *SMALL, "--trials", "3",
                   "--angle-error", "imu", "--output", str(output))
    assert done.returncode == 0, done.stderr
    state = json.loads((output / "state.json").read_text())
    assert state["settings"]["angle_error"] == "imu" and len(state["history"]) == 3
    # Its answers were weighed as an IMU's: resumed as if measured with 5 degrees, refused.
    again = run_cli("personalise", "--oracle", "twin", *WORKER, *SMALL, "--trials", "4",
                    "--output", str(output))
    assert again.returncode == 2 and again.stderr.count("\n") == 1, again.stderr
    assert "angle_error" in again.stderr
    assert len(history(output)) == 3


@pytest.mark.parametrize(("flags", "says"), [
    (["--angle-error", "-1"], "--angle-error -1: not allowed (expected an SD in degrees >= 0, "
                              "or imu)"),
    (["--angle-error", "imu", "--searcher", "cmaes"], "--angle-error imu cannot be used with "
                                                      "--searcher cmaes"),
])
def test_an_angle_error_that_cannot_apply_is_refused_in_one_line(tmp_path, flags, says):
    done = run_cli("personalise", "--oracle", "twin", *WORKER, *SMALL, *flags, "--output",
                   str(tmp_path / "out"))
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert says in done.stderr
    assert not (tmp_path / "out").exists()
