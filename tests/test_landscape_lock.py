"""Processes asking for one landscape at once: the lock holder sweeps it, the others wait and read
it (or sweep it themselves if the holder died); and the door's per-process memo."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest
from filelock import FileLock

from ergohandover.landscape import Landscape, cached_landscape, landscape_key, landscape_of
from ergohandover.landscape.cache import landscape_path
from ergohandover.landscape.grid import Grid
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary

SMALL = Boundary((-0.10, 0.10), (1.00, 1.20), (0.35, 0.50))
WAITING = "another process is sweeping it; waiting"


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def lock_of(key: str) -> FileLock:
    path = landscape_path(key)
    path.parent.mkdir(parents=True, exist_ok=True)
    return FileLock(path.with_name(path.name + ".lock"))


def start(code: str, stderr) -> subprocess.Popen:
    """A Python process running ``code`` (it inherits the test's cache)."""
    return subprocess.Popen([sys.executable, "-c", textwrap.dedent(code)], text=True,
                            stdout=subprocess.PIPE, stderr=stderr)


def wait_for(path, text: str, proc: subprocess.Popen, seconds: float = 60) -> None:
    """Until ``text`` appears in the file ``path`` (a process's stderr)."""
    deadline = time.time() + seconds
    while text not in path.read_text():
        assert proc.poll() is None, f"the process ended first: {path.read_text()}"
        assert time.time() < deadline, f"{text!r} never came: {path.read_text()}"
        time.sleep(0.05)


@pytest.mark.slow
def test_two_sweep_commands_at_once_both_succeed_and_one_computes(cache, tmp_path, monkeypatch):
    grid = Grid(SMALL, 0.01)  # a few seconds with the warm-start lattice: the two overlap
    env = {**os.environ, "ERGOHANDOVER_CACHE": str(cache)}
    procs = [subprocess.Popen(
        [sys.executable, "-m", "ergohandover.cli", "sweep", "--boundary",
         "-0.1,0.1,1.0,1.2,0.35,0.5", "--step", "0.01", "--workers", "1", "--output",
         str(tmp_path / f"out{i}")], env=env, text=True, stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE) for i in range(2)]
    errors = [proc.communicate(timeout=120)[1] for proc in procs]
    assert [proc.returncode for proc in procs] == [0, 0], errors
    manifests = [json.loads((tmp_path / f"out{i}" / "manifest.json").read_text())
                 for i in range(2)]
    assert sorted(m["reused"] for m in manifests) == [False, True]  # exactly one computed it
    assert manifests[0]["landscape"] == manifests[1]["landscape"]
    shared = Landscape.load(manifests[0]["landscape"])
    assert not list((cache / "landscapes").glob("*.parts"))
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "fresh"))
    fresh = landscape_of(Evaluator(), grid, progress=False)
    assert shared.key == fresh.key
    for name, values in fresh.arrays.items():
        np.testing.assert_array_equal(shared.arrays[name], values, err_msg=name)


def test_a_waiting_process_reads_what_the_lock_holder_swept(cache, tmp_path, monkeypatch):
    grid = Grid(SMALL, 0.05)
    key = landscape_key(Evaluator(), grid)
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "elsewhere"))
    made = landscape_of(Evaluator(), grid, progress=False)  # what the holder will have swept
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(cache))
    stderr = tmp_path / "stderr.txt"
    with lock_of(key), stderr.open("w") as sink:  # this test is the holder
        proc = start(f"""
            from ergohandover.landscape import landscapes_of
            from ergohandover.landscape.grid import Grid
            from ergohandover.twin.evaluate import Evaluator
            from ergohandover.twin.task import Boundary
            grid = Grid(Boundary({SMALL.x}, {SMALL.y}, {SMALL.z}), 0.05)
            for done in landscapes_of([Evaluator()], grid, progress=False):
                print(done.reused, done.landscape.path)
        """, sink)
        wait_for(stderr, f"landscape {key}: {WAITING}", proc)
        shutil.copy(made.path, landscape_path(key))  # the holder finishes
    out = proc.communicate(timeout=60)[0]
    assert proc.returncode == 0 and out.split() == ["True", str(landscape_path(key))]
    assert stderr.read_text().count(WAITING) == 1


@pytest.mark.slow
def test_a_waiting_process_sweeps_what_a_dead_holder_left(cache, tmp_path):
    grid = Grid(SMALL, 0.05)
    two = [Evaluator(), Evaluator(BodySpec.from_percentile("p5-female"))]
    dead = landscape_key(two[1], grid)
    holder = start(f"""
        import time
        from filelock import FileLock
        lock = FileLock({str(lock_of(dead).lock_file)!r})
        lock.acquire()
        print("held", flush=True)
        time.sleep(600)
    """, None)
    assert holder.stdout.readline().strip() == "held"
    stderr = tmp_path / "stderr.txt"
    with stderr.open("w") as sink:
        proc = start(f"""
            from ergohandover.landscape import landscapes_of
            from ergohandover.landscape.grid import Grid
            from ergohandover.twin.anthropometry import BodySpec
            from ergohandover.twin.evaluate import Evaluator
            from ergohandover.twin.task import Boundary
            grid = Grid(Boundary({SMALL.x}, {SMALL.y}, {SMALL.z}), 0.05)
            two = [Evaluator(), Evaluator(BodySpec.from_percentile("p5-female"))]
            for done in landscapes_of(two, grid, progress=False):
                print(done.index, done.reused, flush=True)
        """, sink)
        wait_for(stderr, f"landscape {dead}: {WAITING}", proc)  # after sweeping the first
        holder.kill()  # SIGKILL: the OS releases its lock
        holder.wait()
        out = proc.communicate(timeout=60)[0]
    assert proc.returncode == 0, stderr.read_text()
    assert out.splitlines() == ["0 False", "1 False"]
    assert Landscape.load(landscape_path(dead), dead).meta["points_computed"] == grid.size


def test_the_door_memoises_and_looks_up_without_sweeping(cache):
    grid = Grid(SMALL, 0.05)
    assert cached_landscape(Evaluator(), grid) is None
    assert not list(cache.rglob("*.npz"))  # a lookup never sweeps
    first = landscape_of(Evaluator(), grid, progress=False)
    assert first.path == landscape_path(landscape_key(Evaluator(), grid)) and first.path.exists()
    assert landscape_of(Evaluator(), grid, progress=False) is first  # read once per process
    assert cached_landscape(Evaluator(), grid) is first
    loaded = Landscape.load(first.path)
    for name, values in loaded.arrays.items():
        np.testing.assert_array_equal(first.arrays[name], values, err_msg=name)
    with pytest.raises(ValueError, match="read-only"):  # shared by every caller in the process
        first.arrays["reba"][0] = 1
    first.path.unlink()  # a memo never outlives its file
    assert cached_landscape(Evaluator(), grid) is None
    again = landscape_of(Evaluator(), grid, progress=False)
    assert again is not first and again.path.exists()
    np.testing.assert_array_equal(again.arrays["reba"], first.arrays["reba"])
