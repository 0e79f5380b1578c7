"""``ergohandover personalise``: scripted sessions end to end (answers on standard input, in a
file, or from the twin), a bad answer asked again, an interrupted session resumed with the same
proposals, posture rows scored as ``score`` scores them, and one-line refusals of bad flags."""

from __future__ import annotations

import io
import json
import math
import os
import re
import shlex
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from cli_run import wait_for
from conftest import neutral_columns

from ergohandover.cli import build_parser, main
from ergohandover.cli import personalise as command
from ergohandover.envs.scores import SCORE_MAX
from ergohandover.ergonomics import Posture, score_postures
from ergohandover.ergonomics.posture import COLUMN_BY_NAME, POSTURE_COLUMNS, REQUIRED_COLUMNS
from ergohandover.search import AskTellSearcher
from ergohandover.search.answers import SCORE_RANGES, AnswerReader, Refused
from ergohandover.search.oracles import Oracle
from ergohandover.search.session import Session, run
from ergohandover.study.personalise.config import PersonaliseConfig
from ergohandover.study.population.config import PopulationConfig
from ergohandover.twin.anthropometry import BodySpec

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "postures.csv"
SMALL = ["--boundary", "-0.1,0.1,1.0,1.2,0.35,0.5", "--step", "0.05"]  # 5 x 5 x 4 cells
WORKER = ["--stature", "1.62", "--sex", "female"]
PROPOSAL = re.compile(r"^trial (\d+)/\d+: hand the box at (.+)$", re.MULTILINE)


def ask(monkeypatch, capsys, answers: str, output: Path, *flags: str,
        searcher: str = "random-order") -> tuple[int, str, str]:
    """A session answered from ``answers`` on standard input: exit code, stdout, stderr."""
    monkeypatch.setattr(sys, "stdin", io.StringIO(answers))
    capsys.readouterr()
    code = main(["personalise", "--oracle", "ask", "--searcher", searcher, *WORKER,
                 "--output", str(output), *flags])
    out, err = capsys.readouterr()
    return code, out, err


def proposals(out: str) -> list[tuple[int, str]]:
    return [(int(n), where) for n, where in PROPOSAL.findall(out)]


def history(output: Path) -> list[dict]:
    return json.loads((output / "state.json").read_text())["history"]


# Standard input: a bad answer, an interruption, a resume -------------------------------------

def test_a_bad_answer_is_refused_in_one_line_and_asked_again(monkeypatch, capsys, tmp_path):
    code, out, err = ask(monkeypatch, capsys, "6\n7.5x\n5\n", tmp_path / "s", "--trials", "2")
    assert code == 0
    refusals = [line for line in err.splitlines() if line.startswith("refused:")]
    # A person is asked the score an ergonomist reads, REBA, unless --objective says otherwise.
    assert refusals == ["refused: '7.5x' is not an answer: expected a REBA score 1-15, x if the "
                        "worker cannot take the box there, or a posture CSV row"]
    # trial 2 was asked twice, then answered
    assert [n for n, _ in proposals(out)] == [1, 2]
    assert out.split("trial 2/2")[1].count("score (REBA 1-15)") == 2
    assert [h["score"] for h in history(tmp_path / "s")] == [6.0, 5.0]
    assert "reba 5, observed at trial 2; 2 of 2 trials used" in out


def test_a_person_is_proposed_locations_they_can_tell_apart(monkeypatch, capsys, tmp_path):
    """Proposals to a person lie on a grid of --resolution (5 cm by default): no two closer."""
    code, _, _ = ask(monkeypatch, capsys, "6\n5\n4\n6\n5\n7\n", tmp_path / "s", "--trials",
                     "6")
    assert code == 0
    trials = pd.read_csv(tmp_path / "s" / "trials.csv")[["x", "y", "z"]].to_numpy()
    gaps = np.linalg.norm(trials[:, None] - trials[None], axis=-1)[np.triu_indices(6, 1)]
    assert gaps.min() >= 0.05 - 1e-9
    state = json.loads((tmp_path / "s" / "state.json").read_text())
    assert state["settings"]["grid"]["step"] == command.RESOLUTION == 0.05
    line = refused(["--oracle", "ask", "--step", "0.01", "--resolution", "0.05"], tmp_path,
                   capsys)
    assert "--step 0.01 and --resolution 0.05 both given: give one" in line


def test_an_interrupted_session_resumes_with_the_proposals_it_would_have_made(
        monkeypatch, capsys, tmp_path):
    whole = ask(monkeypatch, capsys, "6\n5\n4\nx\n7\n", tmp_path / "whole", "--trials", "5")
    assert whole[0] == 0
    first = ask(monkeypatch, capsys, "6\n5\n", tmp_path / "split", "--trials", "5")
    assert first[0] == command.PAUSED
    assert (f"standard input ended before trial 3's answer; 2 trials saved in "
            f"{tmp_path / 'split' / 'state.json'}: rerun the same command to resume") in first[2]
    assert len(history(tmp_path / "split")) == 2
    assert not (tmp_path / "split" / "trials.csv").exists()  # written at the end only
    second = ask(monkeypatch, capsys, "4\nx\n7\n", tmp_path / "split", "--trials", "5")
    assert second[0] == 0 and "resuming after trial 2" in second[2]
    assert [n for n, _ in proposals(second[1])] == [3, 4, 5]
    assert proposals(first[1])[:2] + proposals(second[1]) == proposals(whole[1])
    columns = ["trial", "x", "y", "z", "feasible", "score", "answer"]
    split = pd.read_csv(tmp_path / "split" / "trials.csv")
    pd.testing.assert_frame_equal(split[columns],
                                  pd.read_csv(tmp_path / "whole" / "trials.csv")[columns])
    best = pd.read_csv(tmp_path / "split" / "recommendation.csv").iloc[0]
    assert (best.score, best.trial, best.trials_used) == (4, 3, 5)
    assert tuple(best[["x", "y", "z"]]) == tuple(split.loc[2, ["x", "y", "z"]])
    manifest = json.loads((tmp_path / "split" / "manifest.json").read_text())
    assert manifest["summary"]["recommendation"]["trial"] == 3
    assert manifest["config"]["searcher"] == "random-order" and manifest["seeds"] == {"searcher": 0}


@pytest.mark.slow
def test_the_acceptance_session_through_the_console_script(tmp_path):
    """``printf '…' | ergohandover personalise --oracle ask …``: a bad answer, standard input
    ending (the interruption), the same command again, a recommendation."""
    script = Path(sys.executable).with_name("ergohandover")
    command_line = (f"{script} personalise --oracle ask --searcher random-order --stature 1.62 "
                    f"--sex female --trials 4 --output {tmp_path / 'run'}")
    first = subprocess.run(["bash", "-c", f"printf '5\\nfive\\n6\\n' | {command_line}"],
                           capture_output=True, text=True, timeout=300)
    assert first.returncode == command.PAUSED, first.stderr
    assert "refused: 'five' is not an answer" in first.stderr
    assert "2 trials saved in" in first.stderr and "Traceback" not in first.stderr
    second = subprocess.run(["bash", "-c", f"printf '3\\n7\\n' | {command_line}"],
                            capture_output=True, text=True, timeout=300)
    assert second.returncode == 0, second.stderr
    assert "resuming after trial 2" in second.stderr
    assert re.search(r"^recommended: hand the box at \d+\.\d cm to the (left|right), "
                     r"\d+\.\d cm up, \d+\.\d cm forward of the floor midway between the "
                     r"worker's feet \(x, y, z = [-+]\d+\.\d, \d+\.\d, \d+\.\d cm\): reba 3, "
                     r"observed at trial 3; "
                     r"4 of 4 trials used$", second.stdout, re.MULTILINE), second.stdout
    for name in ("trials.csv", "recommendation.csv", "manifest.json", "state.json"):
        assert (tmp_path / "run" / name).is_file()


@pytest.mark.parametrize(("signum", "code"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
@pytest.mark.slow
def test_ctrl_c_or_kill_while_asking_loses_no_answer(tmp_path, signum, code):
    out = tmp_path / "run"
    argv = [sys.executable, "-m", "ergohandover.cli", "personalise", "--oracle", "ask",
            "--searcher", "random-order", *WORKER, "--trials", "3", "--output", str(out)]
    run_ = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        run_.stdin.write("6\n5\n")
        run_.stdin.flush()
        wait_for(lambda: (out / "state.json").exists() and len(history(out)) == 2,
                 "two saved answers")
        run_.send_signal(signum)
        _, err = run_.communicate(timeout=60)
    finally:
        if run_.poll() is None:
            run_.kill()
    assert run_.returncode == code
    # One line says both: the stop, and what was kept and how to resume.
    assert err.strip().splitlines()[-1] == (
        f"ergohandover personalise: stopped by {signal.Signals(signum).name}; 2 trials saved in "
        f"{out / 'state.json'}: rerun the same command to resume")
    assert "half-written" not in err and "Traceback" not in err
    assert [h["score"] for h in history(out)] == [6.0, 5.0]
    again = subprocess.run(argv, input="4\n", capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr
    assert "observed at trial 3; 3 of 3 trials used" in again.stdout


def test_a_session_stopped_before_its_first_answer_leaves_no_folder(monkeypatch, capsys,
                                                                    tmp_path):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "stdin", io.StringIO(""))
    assert main(["personalise", "--oracle", "ask", "--searcher", "random-order", *WORKER]) == (
        command.PAUSED)
    assert "no trial was answered, nothing is saved" in capsys.readouterr().err
    assert not list((tmp_path / "runs" / "personalise").iterdir())


# The twin as the oracle --------------------------------------------------------------------

def registered(name: str) -> bool:
    return name in command.registered_searchers()


@pytest.mark.parametrize("searcher", ["random-order", "prior", "bo"])
def test_the_twin_session_is_deterministic_and_recommends_the_twins_score(tmp_path, capsys,
                                                                          searcher):
    if not registered(searcher):
        pytest.skip(f"searcher {searcher!r} is not registered")
    argv = ["personalise", "--oracle", "twin", "--searcher", searcher, "--trials", "5", *SMALL]
    found = []
    for run_ in ("a", "b"):
        assert main([*argv, "--output", str(tmp_path / run_)]) == 0
        found.append(pd.read_csv(tmp_path / run_ / "recommendation.csv"))
    pd.testing.assert_frame_equal(*found)
    best = found[0].iloc[0]
    points = tmp_path / "points.csv"
    points.write_text(f"x,y,z\n{float(best.x)!r},{float(best.y)!r},{float(best.z)!r}\n")
    assert main(["evaluate", "--points", str(points), "--output", str(tmp_path / "e.csv"),
                 "--workers", "1"]) == 0
    assert pd.read_csv(tmp_path / "e.csv")["paper_postural"].iloc[0] == best.score
    trials = pd.read_csv(tmp_path / "a" / "trials.csv")
    assert len(trials) <= 5 and (trials["answer"] == "twin").all()
    assert best.score == trials["score"].min()


def test_the_target_ends_the_session_at_the_first_score_at_or_below_it(tmp_path, capsys):
    assert main(["personalise", "--oracle", "twin", "--searcher", "random-order", "--trials", "50",
                 "--target", "14", *SMALL, "--output", str(tmp_path / "t")]) == 0
    assert "1 of 50 trials used: --target 14 reached" in capsys.readouterr().out
    assert len(pd.read_csv(tmp_path / "t" / "trials.csv")) == 1


# Answers from a file another program appends to ---------------------------------------------

def test_answers_in_a_file_are_matched_to_their_trials(tmp_path, capsys):
    answers = tmp_path / "answers.csv"
    answers.write_text("trial,answer\n# the ergonomist's sheet\n1,6\n2,abc\n2,5\n4,3\n3,x\n")
    assert main(["personalise", "--oracle", "file", "--answer-file", str(answers), "--searcher",
                 "random-order", *WORKER, "--trials", "4", "--output", str(tmp_path / "f")]) == 0
    out, err = capsys.readouterr()
    assert "refused: 'abc' is not an answer" in err
    # a line for a trial not yet proposed waits for its trial
    assert [h["score"] for h in history(tmp_path / "f")] == [6.0, 5.0, None, 3.0]
    assert "paper_postural 3, observed at trial 4" in out
    assert not (tmp_path / "f" / command.PROPOSAL).exists()


@pytest.mark.slow
def test_the_file_oracle_waits_for_the_line_of_the_proposed_trial(tmp_path):
    answers, out = tmp_path / "answers.csv", tmp_path / "f"
    proposal = out / command.PROPOSAL
    run_ = subprocess.Popen([sys.executable, "-m", "ergohandover.cli", "personalise", "--oracle",
                             "file", "--answer-file", str(answers), "--poll", "0.05", "--searcher",
                             "random-order", *WORKER, "--trials", "3", "--output", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        for trial, score in ((1, 7), (2, 4), (3, 9)):  # the other program: reads, answers
            wait_for(lambda t=trial: proposal.exists() and
                     pd.read_csv(proposal)["trial"].iloc[0] == t, f"trial {trial}'s proposal")
            with answers.open("a") as handle:
                handle.write(f"{trial},{score}\n")
        stdout, stderr = run_.communicate(timeout=120)
    finally:
        if run_.poll() is None:
            run_.kill()
    assert run_.returncode == 0, stderr
    assert "waiting for a line '1,ANSWER'" in stderr
    assert "paper_postural 4, observed at trial 2; 3 of 3 trials used" in stdout


# Posture rows ------------------------------------------------------------------------------

def scored(table: pd.DataFrame, tmp_path: Path, objective: str) -> list[float]:
    """``ergohandover score``'s ``objective`` of every row of ``table``."""
    source, result = tmp_path / "postures.csv", tmp_path / "scores.csv"
    table.to_csv(source, index=False)
    assert main(["score", "--input", str(source), "--output", str(result)]) == 0
    return pd.read_csv(result)[objective].astype(float).tolist()


def test_a_posture_row_is_scored_as_the_score_command_scores_it(monkeypatch, capsys, tmp_path):
    example = pd.read_csv(EXAMPLE, dtype=str)
    required = example[list(REQUIRED_COLUMNS)].iloc[[0]]  # 24 values, the contract's order
    full = example.iloc[[1]].copy()  # 38 values: every column, absent ones at their default
    for name in POSTURE_COLUMNS:
        if name not in full:
            column = COLUMN_BY_NAME[name]
            full[name] = full[column.same_as] if column.same_as else f"{column.default:g}"
    full = full[list(POSTURE_COLUMNS)]
    header, row = EXAMPLE.read_text().splitlines()[:4:3]  # the file's header, third row
    answers = "\n".join([",".join(required.iloc[0]), ",".join(full.iloc[0]), header, row, ""])
    code, _, err = ask(monkeypatch, capsys, answers, tmp_path / "s", "--trials", "3",
                       "--objective", "reba")
    assert code == 0, err
    assert "posture header noted: 27 columns" in err
    expected = [*scored(required, tmp_path, "reba"), *scored(full, tmp_path, "reba"),
                scored(example, tmp_path, "reba")[2]]
    assert [h["score"] for h in history(tmp_path / "s")] == expected
    assert history(tmp_path / "s")[2]["answer"] == row  # the row itself is kept


# The answers themselves --------------------------------------------------------------------

@pytest.mark.parametrize(("line", "problem"), [
    ("", "nothing typed: expected a paper postural score 3-14"),
    ("abc", "'abc' is not an answer: expected a paper postural score 3-14, x if the worker"),
    ("2", "'2' is outside 3-14, the range of paper postural"),
    ("15", "'15' is outside 3-14"),
    ("nan", "'nan' is outside 3-14"),
    ("1,2,3", "a posture row of 3 values: expected 24 (the required Posture columns"),
    ("trunk_flexion,neck_flexion", "a posture header line without column 'trunk_side_bend'"),
])
def test_what_is_not_an_answer_is_refused_naming_it(line, problem):
    with pytest.raises(Refused) as caught:
        AnswerReader("paper_postural").read(line)
    assert problem in str(caught.value) and "\n" not in str(caught.value)


def test_scores_infeasible_and_fractions_are_answers():
    reader = AnswerReader("rula")
    assert reader.read(" 3\n") == (3.0, "score", "3", None)  # a score carries no posture
    assert reader.read("4.5").score == 4.5  # the mean of two raters
    assert reader.read("4,5").score == 4.5  # as a decimal comma writes it, not a posture row
    with pytest.raises(Refused, match="outside 1-7"):
        reader.read("7,5")
    assert all(math.isinf(reader.read(t).score) for t in ("x", "X", "infeasible"))


def test_each_objectives_range_is_what_its_scorer_can_give():
    postures = Posture.random(20_000, np.random.default_rng(0))
    lowest = Posture(neutral_columns(left_upper_arm_flexion=-30.0, right_upper_arm_flexion=-30.0,
                                     left_elbow_flexion=30.0, right_elbow_flexion=30.0))
    neutral = Posture(neutral_columns())
    for objective, (lo, hi) in SCORE_RANGES.items():
        assert hi == SCORE_MAX[objective]
        values = score_postures(postures)[objective]
        assert lo <= values.min() and values.max() <= hi
        reached = min(score_postures(p)[objective][0] for p in (lowest, neutral))
        assert reached == lo, objective


# The loop itself: a searcher that proposes a known location again ----------------------------

class Cycle(AskTellSearcher):
    """Proposes cells 0, 1, 0, 2, 3, ... (one repeat)."""

    name = "cycle"
    ORDER = (0, 1, 0, 2, 3, 4, 5)

    def __init__(self, grid, seed=0, prior=None):
        super().__init__(grid, seed, prior)
        self.asked, self.told = 0, []

    def ask(self) -> int:
        self.asked += 1
        return self.ORDER[self.asked - 1]

    def tell(self, cell, answer) -> None:  # every answer as an Answer: its score is read
        self.told.append((cell, answer.score))


class Scores(Oracle):
    def answer(self, proposal):
        from ergohandover.search.answers import Answer

        return Answer(10.0 - proposal.cell, "score", f"{10 - proposal.cell}")


def test_a_repeated_proposal_is_told_the_known_answer_and_costs_no_trial(tmp_path):
    from ergohandover.cli.options import grid_from_args
    from ergohandover.twin.evaluate import Evaluator

    grid = grid_from_args(Evaluator(), SMALL[1], 0.05)
    session = Session(tmp_path / "state.json", {"searcher": "cycle"})
    searcher = Cycle(grid)
    assert run(session, searcher, Scores(), budget=3, say=lambda _: None) == "budget"
    assert [r.trial for r in session.history] == [1, 2, 3]  # the repeat is no trial
    assert searcher.told == [(0, 10.0), (1, 9.0), (0, 10.0), (2, 8.0)]
    resumed = Session.open(tmp_path / "state.json", {"searcher": "cycle"})
    again = resumed.resume(Cycle(grid))  # answers the repeat again: the same next proposal
    assert again.told == searcher.told and again.ask() == 3
    assert resumed.best().trial.trial == 3
    # A state file that lists the repeat (trial null) reads the same.
    state = json.loads((tmp_path / "state.json").read_text())
    state["history"].insert(2, {**state["history"][0], "trial": None})
    (tmp_path / "old.json").write_text(json.dumps(state))
    old = Session.open(tmp_path / "old.json", {"searcher": "cycle"})
    assert old.history == resumed.history and old.resume(Cycle(grid)).ask() == 3


# Bad flags: one line, exit code 2, nothing written ------------------------------------------

BAD = [
    (["--oracle", "maybe"], "--oracle maybe: not one of twin, ask, file"),
    (["--oracle", "file", *WORKER], "--oracle file needs --answer-file CSV"),
    (["--oracle", "ask", "--poll", "2", *WORKER], "--poll cannot be used with --oracle ask"),
    (["--oracle", "twin", "--answer-file", "a.csv"],
     "--answer-file cannot be used with --oracle twin"),
    (["--oracle", "twin", "--answers", "pairwise", "--searcher", "prior"],
     "--answers pairwise: --searcher prior is told scores"),
    (["--oracle", "twin", "--searcher", "pairwise", "--answers", "scores"],
     "--answers scores: --searcher pairwise is told preferences"),
    (["--oracle", "twin", "--answers", "pairwise", "--target", "4"],
     "--target cannot be used with --answers pairwise"),
    (["--oracle", "ask", "--answers", "pairwise", "--answer-format", "keypoints:coco17",
      *WORKER], "--answer-format cannot be used with --answers pairwise"),
    (["--oracle", "ask"], "--oracle ask needs the worker: give --stature M and --sex"),
    (["--oracle", "twin", "--trials", "0"], "--trials 0: must be >= 1"),
    (["--oracle", "twin", "--trials", "101", *SMALL],
     "--trials 101: more than the grid's 100 locations"),
    (["--oracle", "twin", "--target", "20"], "--target 20: outside 3-14, the range of "
     "--objective paper_postural"),
    (["--oracle", "twin", "--searcher", "nope"], "--searcher nope: not one of "),
    (["--oracle", "twin", "--poll", "0"], "--poll 0: must be > 0 s"),
    (["--oracle", "twin", "--stature", "3"], "--stature 3: outside 1.4-2.1 m"),
    (["--oracle", "twin", "--step", "0.5", *SMALL[:2]], "--step 0.5: larger than the boundary"),
]


def refused(argv: list[str], tmp_path: Path, capsys) -> str:
    before = sorted(tmp_path.rglob("*"))
    capsys.readouterr()
    assert main(["personalise", *argv]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith("ergohandover personalise: error: ")
    assert sorted(tmp_path.rglob("*")) == before, "a refused command wrote something"
    return err


@pytest.mark.parametrize(("argv", "message"), BAD)
def test_a_bad_flag_is_one_line_and_writes_nothing(tmp_path, capsys, monkeypatch, argv,
                                                   message):
    monkeypatch.chdir(tmp_path)  # the default output folder would be made here
    assert message in refused([*argv, "--output", str(tmp_path / "out")], tmp_path, capsys)


def test_a_state_of_other_settings_or_no_state_at_all_is_refused(tmp_path, capsys,
                                                                 monkeypatch):
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "s"
    assert ask(monkeypatch, capsys, "6\n", out, "--trials", "2")[0] == command.PAUSED
    state = (out / "state.json").read_bytes()
    argv = ["--oracle", "ask", "--searcher", "random-order", *WORKER, "--output", str(out)]
    err = refused([*argv, "--seed", "1"], tmp_path, capsys)
    assert (f"--output {out}: its session was made with seed = 0, this command has 1 "
            "(--seed): rerun that session's command") in err
    err = refused([*argv, "--sex", "male"], tmp_path, capsys)
    # A man of the same stature is another body: the first field that differs is named.
    man = BodySpec.from_measurements({"stature_m": 1.62}, "male")
    assert (f"evaluator.body.mass_kg = 67.0, this command has {man.mass_kg:g} (the worker's "
            "flags)") in err
    assert (out / "state.json").read_bytes() == state
    other = tmp_path / "other.json"
    other.write_text('{"format": "something else"}')
    err = refused([*argv, "--state", str(other)], tmp_path, capsys)
    assert f"--state {other}: not a personalise state file" in err


# Help and defaults --------------------------------------------------------------------------

def test_the_help_lists_every_flag_and_the_defaults_are_the_studys():
    parser = build_parser().commands["personalise"]
    text = parser.format_help()
    for flag in ("--oracle", "--answers", "--answer-file", "--poll", "--searcher", "--no-prior",
                 "--trials", "--target", "--seed", "--objective", "--boundary", "--step",
                 "--stature", "--sex", "--state", "--output"):
        assert flag in text, flag
    assert f"exit code {command.PAUSED}" in text and "docs/personalise.md" in text
    population = PopulationConfig()
    assert (population.boundary, population.step) == (command.BOUNDARY, command.STEP)
    assert command.DEFAULT_TRIALS in PersonaliseConfig().budgets
    assert (ROOT / "docs" / "personalise.md").is_file()


def test_the_default_searcher_is_registered():
    assert command.DEFAULT_SEARCHER in command.registered_searchers()


@pytest.mark.slow
def test_the_documented_session_is_what_the_command_prints(tmp_path):
    """docs/personalise.md's example session, rerun: the same proposals, refusals, pause,
    resume and recommendation, line for line."""
    text = (ROOT / "docs" / "personalise.md").read_text().split("## An example session")[1]
    block = re.search(r"```\n(\$ .*?)```", text, re.S).group(1)
    commands = [line[2:] for line in block.splitlines() if line.startswith("$ ")]
    # each command runs with the previous one's exit status in $? (for `echo $?`)
    script = "s=0\n" + "\n".join(f"echo {shlex.quote('$ ' + c)}; (exit $s); {c} 2>&1; s=$?"
                                  for c in commands)
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    result = subprocess.run(["bash", "-c", script], cwd=tmp_path, env=env, capture_output=True,
                            text=True, timeout=300)
    assert [line.rstrip() for line in result.stdout.splitlines()] == block.splitlines()
