"""Stopping cleanly: SIGTERM or Ctrl-C in the middle of a part stops the study and its worker
processes within seconds, leaves no orphan and no half-written folder, and a rerun resumes."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from ergohandover.executor import clean_stop
from ergohandover.study.resume import STAGING, run_part

ROOT = Path(__file__).resolve().parents[1]


def session_processes(sid: int) -> list[int]:
    """Every live process of a session (zombies, already dead, are left out)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        # after the command's closing parenthesis: state, ppid, pgrp, session, ...
        fields = stat.rsplit(")", 1)[1].split()
        if int(fields[3]) == sid and fields[0] != "Z":
            found.append(int(entry.name))
    return found


def wait_for(condition, timeout: float, what: str) -> None:
    end = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > end:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.2)


@pytest.mark.slow
@pytest.mark.parametrize("engine", ["local", "ray"])
def test_sigterm_mid_part_stops_every_process_and_a_rerun_resumes(tmp_path, engine):
    """Ray's processes (its GCS, raylet, workers) are in the study's session too."""
    results, log = tmp_path / "results", tmp_path / "run.log"
    env = {**os.environ, "ERGOHANDOVER_CACHE": str(tmp_path / "cache")}
    command = [sys.executable, str(ROOT / "experiments" / "run_all.py"), "--quick",
               "--engine", engine, "--workers", "2", "--results", str(results),
               "--only", "learning"]
    with open(log, "w") as out:
        # A session of its own: every process it starts can be found by its session id.
        run = subprocess.Popen(command, cwd=ROOT, env=env, stdout=out, stderr=subprocess.STDOUT,
                               start_new_session=True)
    try:
        # Mid-part: the learning runs are under way, on the pool's two workers.
        wait_for(lambda: "learning (" in log.read_text() and
                 len(session_processes(run.pid)) >= 3, 300, "the learning part's pool")
        time.sleep(2)
        staged = results / STAGING / "learning"
        assert staged.is_dir()  # the part writes into its staging folder
        os.kill(run.pid, signal.SIGTERM)  # the parent only, as `kill PID` does
        assert run.wait(timeout=30) == 143
        wait_for(lambda: not session_processes(run.pid), 10, "the workers to exit")
    finally:
        if run.poll() is None or session_processes(run.pid):
            os.killpg(run.pid, signal.SIGKILL)
    text = log.read_text()
    assert "stopped by SIGTERM; finished parts are kept and a rerun resumes" in text
    assert "Traceback" not in text
    # The landscape part had finished (its manifest is there); the learning part left nothing.
    assert (results / "landscape" / "manifest.json").is_file()
    assert not (results / "learning").exists()
    assert not (results / STAGING).exists()

    rerun = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True,
                           timeout=600)
    assert rerun.returncode == 0, rerun.stderr[-2000:]
    assert "[landscape] reusing finished results" in rerun.stdout
    assert (results / "learning" / "manifest.json").is_file()
    assert (results / "learning" / "runs.csv").is_file()
    assert not (results / STAGING).exists()


def test_a_failing_part_keeps_the_previous_results_and_leaves_no_staging(tmp_path):
    folder = tmp_path / "part"

    def first(out: Path) -> None:
        (out / "table.csv").write_text("a\n1\n")

    assert run_part("part", folder, {"n": 1}, first)
    before = sorted(p.name for p in folder.iterdir())

    def broken(out: Path) -> None:
        (out / "table.csv").write_text("a\n")  # half of what it meant to write
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_part("part", folder, {"n": 2}, broken)
    assert sorted(p.name for p in folder.iterdir()) == before
    assert (folder / "table.csv").read_text() == "a\n1\n"
    assert not (tmp_path / STAGING).exists()


def test_a_finished_part_replaces_the_old_folder_whole(tmp_path):
    folder = tmp_path / "part"

    def writes(name: str):
        def work(out: Path) -> None:
            (out / name).write_text("a\n1\n")
        return work

    run_part("part", folder, {"n": 1}, writes("old.csv"))
    run_part("part", folder, {"n": 2}, writes("new.csv"))
    # Nothing of the previous run lingers beside the new one.
    assert sorted(p.name for p in folder.iterdir()) == ["manifest.json", "new.csv"]
    assert json.loads((folder / "manifest.json").read_text())["result"] == "part"


def _sleep_then(job: float) -> float:
    time.sleep(job)
    return job


@pytest.mark.slow
def test_clean_stop_turns_sigterm_into_exit_143_and_terminates_the_pool(tmp_path):
    started = tmp_path / "started"
    script = f"""
import os, sys, time
sys.path.insert(0, {str(ROOT / 'tests')!r})
from ergohandover.executor import LocalExecutor, clean_stop
from test_interrupts import _sleep_then
with clean_stop():
    with LocalExecutor(2) as pool:
        open({str(started)!r}, "w").write("pool")
        list(pool.map(_sleep_then, [60.0, 60.0]))
"""
    run = subprocess.Popen([sys.executable, "-c", script], stderr=subprocess.PIPE, text=True,
                           start_new_session=True)
    try:
        wait_for(lambda: started.exists() and len(session_processes(run.pid)) == 3, 60,
                 "the pool's two workers")
        os.kill(run.pid, signal.SIGTERM)  # the parent only
        assert run.wait(timeout=20) == 143
        assert "stopped by SIGTERM" in run.stderr.read()
        wait_for(lambda: not session_processes(run.pid), 10, "the pool's workers to exit")
    finally:
        if run.poll() is None or session_processes(run.pid):
            os.killpg(run.pid, signal.SIGKILL)


def test_clean_stop_restores_the_callers_handlers():
    before = signal.getsignal(signal.SIGTERM)
    with clean_stop():
        assert signal.getsignal(signal.SIGTERM) is not before
    assert signal.getsignal(signal.SIGTERM) is before


def test_a_just_forked_worker_that_still_holds_the_handler_dies_at_sigterm():
    """A pool may terminate a worker between its fork and its initialiser, while it still has
    the parent's handler: it must die, not raise in the parent's place and live on (which would
    leave the pool's terminate waiting for it)."""
    with clean_stop():
        pid = os.fork()
        if pid == 0:  # the child: dies at SIGTERM, or exits 0 if the signal was swallowed
            try:
                time.sleep(30)
            finally:
                os._exit(0)
        time.sleep(0.2)
        os.kill(pid, signal.SIGTERM)
        _, status = os.waitpid(pid, 0)
    assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGTERM
