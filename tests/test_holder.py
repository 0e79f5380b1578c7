"""One writer at a time (:mod:`ergohandover.io.holder`): a second run on a held folder or state
is refused in one line naming the first, before it reads or writes anything; a killed holder
blocks nothing; a finished one leaves nothing behind. Exercised by hand, by ``ergohandover
personalise`` (two sessions on one --output) and by ``run_all.py`` (two runs on one
--results)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from cli_run import run_cli, wait_for

from ergohandover.io.holder import HeldError, hold

ROOT = Path(__file__).resolve().parents[1]
HOLD = ("import sys, time; from ergohandover.io.holder import hold\n"
        "with hold(sys.argv[1], 'the folder', 'wait'):\n"
        "    print('held', flush=True); time.sleep(600)\n")


def holding(path: Path) -> subprocess.Popen:
    """Another process holding ``path`` (returns once it holds it)."""
    other = subprocess.Popen([sys.executable, "-c", HOLD, str(path)], stdout=subprocess.PIPE,
                             text=True)
    assert other.stdout.readline().strip() == "held"
    return other


def test_a_held_path_is_refused_naming_its_holder_and_freed_when_the_holder_dies(tmp_path):
    target = tmp_path / "results"
    other = holding(target)
    try:
        with pytest.raises(HeldError) as refused, hold(target, "--results results", "wait"):
            pass
        message = str(refused.value)
        assert message.startswith(f"--results results is in use by process {other.pid} (")
        assert message.endswith("): wait") and "\n" not in message
    finally:
        other.send_signal(signal.SIGKILL)  # killed, as a run can be: the OS frees the lock
        other.wait()
    with hold(target, "--results results", "wait"):
        assert (tmp_path / ".results.holder").read_text().startswith(f"process {os.getpid()}")
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # nothing left behind


def test_two_personalise_sessions_on_one_output_lose_no_answer(tmp_path):
    out = tmp_path / "run"
    argv = ["personalise", "--oracle", "ask", "--searcher", "random-order", "--stature", "1.62",
            "--sex", "female", "--trials", "3", "--output", str(out)]
    first = subprocess.Popen([sys.executable, "-m", "ergohandover.cli", *argv],
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        first.stdin.write("6\n5\n")
        first.stdin.flush()
        wait_for(lambda: (out / "state.json").exists() and len(
            json.loads((out / "state.json").read_text())["history"]) == 2, "two answers")
        before = (out / "state.json").read_bytes()
        second = run_cli(*argv, stdin="1\n1\n1\n")
        assert second.returncode == 2
        assert second.stderr.strip() == (
            f"ergohandover personalise: error: --output {out} is in use by process "
            f"{first.pid} ({second.stderr.split(' (', 1)[1].split(')')[0]}): wait for that "
            "session to end, or give another --output")
        assert "trial 1" not in second.stdout  # refused before it proposed anything
        assert (out / "state.json").read_bytes() == before
        first.stdin.write("4\n")
        first.stdin.flush()
        stdout, _ = first.communicate(timeout=300)
        assert "3 of 3 trials used" in stdout
    finally:
        if first.poll() is None:
            first.kill()
    assert first.returncode == 0
    assert [h["score"] for h in json.loads((out / "state.json").read_text())["history"]] == [
        6.0, 5.0, 4.0]
    assert not list(tmp_path.glob(".*"))  # the hold is gone with the session


def test_a_second_run_all_on_one_results_folder_is_one_line_and_writes_nothing(tmp_path):
    results = tmp_path / "rq"
    other = holding(results)
    try:
        run = subprocess.run([sys.executable, str(ROOT / "experiments" / "run_all.py"),
                              "--quick", "--only", "validation", "--results", str(results)],
                             capture_output=True, text=True, timeout=600)
    finally:
        other.kill()
        other.wait()
    assert run.returncode == 2
    line = run.stderr.strip()
    assert line.startswith(f"run_all: error: --results {results} is in use by process "
                           f"{other.pid} (") and "\n" not in line, run.stderr
    assert line.endswith("wait for that run to end, or give another --results")
    assert not results.exists() or not any(results.iterdir())
