"""Many workers' landscapes through the door (``landscapes_of``) and one executor interface:
the local pool and a real local Ray instance give the same landscapes (the same as
``landscape_of`` of one worker), a killed run resumes without recomputing finished workers, and
bad engines and chunks are one-line errors."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from ergohandover.errors import ConfigError
from ergohandover.executor import LocalExecutor
from ergohandover.landscape import landscape_key, landscape_of, landscapes_of
from ergohandover.landscape.cache import checksum, landscape_path
from ergohandover.landscape.grid import Grid
from ergohandover.study.engines import RayExecutor, check_address, make_executor
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary

SMALL = Boundary((-0.10, 0.10), (0.90, 1.20), (0.30, 0.50))
TWO = [Evaluator(BodySpec(1.58, 55.0, "female")), Evaluator(BodySpec(1.86, 97.0, "male"))]


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def swept(grid, evaluators, executor, **kwargs) -> dict[int, object]:
    return {f.index: f for f in landscapes_of(evaluators, grid, executor=executor,
                                              progress=False, **kwargs)}


@pytest.mark.slow
def test_ray_and_the_local_pool_give_identical_landscapes_for_two_workers(cache, tmp_path,
                                                                         monkeypatch):
    # Ray is installed with the test extras: this runs on a real local instance.
    grid = Grid(SMALL, 0.05)
    local = swept(grid, TWO, LocalExecutor(2), chunk=60)
    assert {f.index for f in local.values() if not f.reused} == {0, 1}
    monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / "ray_cache"))
    with RayExecutor(2) as executor:
        assert executor.cpus == 2
        on_ray = swept(grid, TWO, executor, chunk=60)
    for i, evaluator in enumerate(TWO):
        assert not on_ray[i].reused
        assert on_ray[i].landscape.key == local[i].landscape.key == landscape_key(evaluator, grid)
        for name, values in local[i].landscape.arrays.items():
            np.testing.assert_array_equal(on_ray[i].landscape.arrays[name], values,
                                          err_msg=name)
        # ... and both are what the one-worker sweep writes.
        monkeypatch.setenv("ERGOHANDOVER_CACHE", str(tmp_path / f"single_{i}"))
        single = landscape_of(evaluator, grid, progress=False)
        assert checksum(single.arrays) == checksum(local[i].landscape.arrays)
    # The two workers really differ (a test of identical results needs different inputs).
    assert checksum(local[0].landscape.arrays) != checksum(local[1].landscape.arrays)


@pytest.mark.slow
def test_finished_workers_come_from_the_cache(cache):
    grid = Grid(SMALL, 0.1)
    first = swept(grid, TWO[:1], None)
    again = swept(grid, TWO, None)
    assert again[0].reused and not again[1].reused
    np.testing.assert_array_equal(again[0].landscape.arrays["paper_postural"],
                                  first[0].landscape.arrays["paper_postural"])


@pytest.mark.slow
def test_the_same_worker_twice_is_swept_once(cache):
    grid = Grid(SMALL, 0.1)
    done = swept(grid, [TWO[0], TWO[1], TWO[0]], LocalExecutor(2))
    assert sorted(done) == [0, 1, 2] and not any(f.reused for f in done.values())
    assert done[0].landscape is done[2].landscape
    assert done[0].landscape.meta["points_computed"] == grid.size


@pytest.mark.slow
def test_a_killed_population_sweep_resumes_without_recomputing_finished_workers(cache):
    bodies = [(1.55 + 0.05 * k, 50.0 + 5 * k, "female" if k % 2 else "male") for k in range(6)]
    evaluators = [Evaluator(BodySpec(*b)) for b in bodies]
    grid = Grid(SMALL, 0.04)
    script = textwrap.dedent(f"""
        from ergohandover.landscape.grid import Grid
        from ergohandover.landscape import landscapes_of
        from ergohandover.twin.anthropometry import BodySpec
        from ergohandover.twin.evaluate import Evaluator
        from ergohandover.twin.task import Boundary
        grid = Grid(Boundary({SMALL.x}, {SMALL.y}, {SMALL.z}), 0.04)
        evaluators = [Evaluator(BodySpec(*b)) for b in {bodies}]
        for _ in landscapes_of(evaluators, grid, progress=False):
            pass
    """)
    proc = subprocess.Popen([sys.executable, "-c", script])  # inherits the test's cache
    files = [landscape_path(landscape_key(e, grid)) for e in evaluators]
    deadline = time.time() + 180
    while sum(f.exists() for f in files) < 2 and time.time() < deadline:
        time.sleep(0.05)
    proc.kill()  # SIGKILL mid-sweep: no clean-up runs
    proc.wait()
    finished = [f for f in files if f.exists()]
    assert 2 <= len(finished) < len(files), "the kill came too late to test a resume"
    stamps = {f: f.stat().st_mtime_ns for f in finished}
    resumed = swept(grid, evaluators, None)
    assert {i for i, f in resumed.items() if f.reused} == {files.index(f) for f in finished}
    assert all(f.stat().st_mtime_ns == stamps[f] for f in finished)  # never rewritten
    assert all(f.exists() for f in files)
    for path in files:  # the same landscapes as an uninterrupted sweep
        path.unlink()
    uninterrupted = swept(grid, evaluators, None)
    for i in range(len(evaluators)):
        assert not uninterrupted[i].reused
        assert checksum(uninterrupted[i].landscape.arrays) == \
            checksum(resumed[i].landscape.arrays)


def test_bad_engines_and_addresses_are_one_line_errors():
    with pytest.raises(ConfigError, match="engine = 'dask' is not allowed"):
        make_executor("dask")
    with pytest.raises(ConfigError, match="address = 'auto' needs engine = 'ray'"):
        make_executor("local", 2, "auto")
    for bad in ("nohost", "host:port", ":6379", "10.0.0.5:99999"):
        with pytest.raises(ConfigError, match="is not valid \\(use auto or HOST:PORT"):
            check_address(bad)
    assert check_address("10.0.0.5:6379") == "10.0.0.5:6379" and check_address("auto") == "auto"
    with pytest.raises(ConfigError, match="workers = 0 is outside the valid range"):
        make_executor("ray", 0)


def test_a_bad_chunk_is_refused_before_any_work(cache):
    with pytest.raises(ValueError, match="chunk = 0 is outside the valid range"):
        landscapes_of(TWO, Grid(SMALL, 0.1), chunk=0)
    assert not list(cache.glob("landscapes/*.npz"))
