"""``ergohandover personalise --answers pairwise``: a session told only which of the last two
handovers was better — asked, refused, interrupted by Ctrl-C and resumed, answered by the twin."""

from __future__ import annotations

import io
import json
import signal
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from cli_run import wait_for

from ergohandover.cli import main
from ergohandover.search.pairwise import preferred
from ergohandover.search.preferences import BETTER, SAME, WORSE

WORKER = ["--stature", "1.62", "--sex", "female"]


def history(output: Path) -> list[dict]:
    return json.loads((output / "state.json").read_text())["history"]


def ask(monkeypatch, capsys, answers: str, output: Path, *flags: str):
    monkeypatch.setattr(sys, "stdin", io.StringIO(answers))
    capsys.readouterr()
    code = main(["personalise", "--oracle", "ask", "--answers", "pairwise", *WORKER,
                 "--output", str(output), *flags])
    out, err = capsys.readouterr()
    return code, out, err


def test_a_pairwise_session_asks_for_comparisons_and_recommends_the_models_choice(
        monkeypatch, capsys, tmp_path):
    code, out, err = ask(monkeypatch, capsys, "ok\nmaybe\nworse\nx\nbetter\nsame\n",
                         tmp_path / "s", "--trials", "5")
    assert code == 0, err
    assert "searcher pairwise" in err  # the searcher told preferences, by default
    assert ("refused: 'maybe' is not an answer: expected better, worse or same (b, w, s): this "
            "handover against trial 1's, or x if the worker cannot take the box there") in err
    assert "better, worse or same than trial 2's handover" in out
    # Trial 4 is compared with trial 2, the last the worker could take.
    assert "better, worse or same than trial 2's handover, or 'x' if the worker cannot take " \
           "it there: better" in out.split("trial 4/5")[1]
    saved = history(tmp_path / "s")
    answers = [h["score"] for h in saved]
    assert answers == [SAME, WORSE, None, BETTER, SAME]
    told = [float("inf") if a is None else a for a in answers]
    best = preferred_cell(saved, told)
    result = pd.read_csv(tmp_path / "s" / "recommendation.csv").iloc[0]
    assert result.trial == best and result.answers == "pairwise"
    assert 0 < result.p_best_of_tried <= 1 and result.feasible_tried == 4
    assert f"the handover preferred most (trial {best}); 5 of 5 trials used" in out
    assert "uncertainty: the preference model gives it a" in out
    trials = pd.read_csv(tmp_path / "s" / "trials.csv")
    assert trials["score"].isna().all()
    assert list(trials["answer"]) == ["ok", "worse", "x", "better", "same"]


def preferred_cell(saved: list[dict], told: list[float]) -> int:
    """The trial number the preference model prefers, recomputed from the saved history."""
    from ergohandover.landscape.grid import Grid
    from ergohandover.twin.task import Boundary

    grid = Grid(Boundary((-0.2, 0.2), (0.72, 1.44), (0.3, 0.6)), 0.01)  # the command's grid
    cells = [grid.nearest_cell((h["x"], h["y"], h["z"])) for h in saved]
    return saved[preferred(grid, cells, told)]["trial"]


@pytest.mark.slow
def test_a_pairwise_session_stopped_by_ctrl_c_resumes_with_the_same_proposals(tmp_path):
    argv = [sys.executable, "-m", "ergohandover.cli", "personalise", "--oracle", "ask",
            "--answers", "pairwise", *WORKER, "--trials", "4"]
    whole = subprocess.run([*argv, "--output", str(tmp_path / "whole")],
                           input="ok\nbetter\nworse\nbetter\n", capture_output=True, text=True,
                           timeout=300)
    assert whole.returncode == 0, whole.stderr
    out = tmp_path / "split"
    run_ = subprocess.Popen([*argv, "--output", str(out)], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        run_.stdin.write("ok\nbetter\n")
        run_.stdin.flush()
        wait_for(lambda: (out / "state.json").exists() and len(history(out)) == 2,
                 "two saved answers")
        run_.send_signal(signal.SIGINT)
        _, err = run_.communicate(timeout=60)
    finally:
        if run_.poll() is None:
            run_.kill()
    assert run_.returncode == 130, err
    assert "2 trials saved in" in err and "Traceback" not in err
    again = subprocess.run([*argv, "--output", str(out)], input="worse\nbetter\n",
                           capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr
    assert "resuming after trial 2" in again.stderr
    assert "better, worse or same than trial 2's handover" in again.stdout
    columns = ["trial", "x", "y", "z", "answer"]
    pd.testing.assert_frame_equal(pd.read_csv(out / "trials.csv")[columns],
                                  pd.read_csv(tmp_path / "whole" / "trials.csv")[columns])
    assert again.stdout.splitlines()[-2:] == whole.stdout.splitlines()[-2:]


def test_the_twin_answers_preferences_from_its_scores(tmp_path, capsys):
    small = ["--boundary", "-0.1,0.1,1.0,1.2,0.35,0.5", "--step", "0.05"]
    code = main(["personalise", "--oracle", "twin", "--answers", "pairwise", *small,
                 "--trials", "6", "--output", str(tmp_path / "t")])
    out = capsys.readouterr().out
    assert code == 0
    said = [line.split(": ", 1)[1].split(" ")[0] for line in out.splitlines()
            if line.startswith("twin: ")]
    assert len(said) == 6 and said[0] in ("ok", "x")
    assert set(said) <= {"ok", "x", "better", "worse", "same"}
    manifest = json.loads((tmp_path / "t" / "manifest.json").read_text())
    assert manifest["config"]["answers"] == "pairwise"
    assert manifest["config"]["searcher"] == "pairwise"
