"""The one door to landscapes: every module outside this package gets a cached landscape from
:func:`landscape_of`, :func:`landscapes_of` or :func:`cached_landscape`, never from a path.

A landscape comes from this process's memo, else from the cache's file, else it is swept into
the cache (:mod:`~ergohandover.landscape.sweep`). Two processes may ask for the same landscape
at once (two ``ergohandover sweep`` commands, the jobs of a study): only the holder of the
landscape's lock, ``<key>.npz.lock`` beside its file, sweeps it; the others wait, then read the
file it wrote. After taking a lock the cache is looked at again, since the previous holder may
just have finished. The lock is :class:`filelock.FileLock`, an OS ``flock`` that the OS releases
when its process dies: a lock file left behind never blocks a later run, and a process that died
mid-sweep leaves its finished chunks to whoever takes the lock next.

The memo keeps the last few landscapes returned by :func:`landscape_of` and
:func:`cached_landscape`, so a worker process that runs many jobs on one landscape reads its
file once. An entry is checked against its file's identity on every call (a file replaced or
removed is read again), and its arrays are read-only, since every caller in the process shares
them.
"""

from __future__ import annotations

import sys
import time
from collections import OrderedDict
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import NamedTuple

from filelock import FileLock, Timeout

from ..executor import Executor, LocalExecutor, check_workers
from ..twin.evaluate import Evaluator, posture_solver
from . import sweep as _sweep
from .cache import Landscape, LandscapeError, landscape_key, landscape_path
from .grid import Grid
from .sweep import CHUNK_POINTS, Plan, check_chunk, task_points

__all__ = ["CHUNK_POINTS", "Finished", "cached_landscape", "landscape_of", "landscapes_of"]

MEMO_ENTRIES = 8
MEMO_BYTES = 1 << 30
"""The memo holds at most this many landscapes and (beyond the newest) bytes of arrays: a 3 mm
paper-code landscape is 160 MB."""
MAX_HELD_LOCKS = 256
"""Locks (each an open file) that :func:`landscapes_of` holds at once; more landscapes are
swept in rounds."""


class Finished(NamedTuple):
    """One landscape as it arrives: its index in the evaluators given, and whether it was read
    from the cache (``reused``, also when another process swept it while this one waited) or
    computed, wholly or in part, by this call."""

    index: int
    landscape: Landscape
    reused: bool


_MEMO: OrderedDict[Path, tuple[tuple, Landscape]] = OrderedDict()


def _identity(path: Path) -> tuple | None:
    try:
        st = path.stat()
    except OSError:
        return None
    return st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns


def _recall(path: Path) -> Landscape | None:
    entry = _MEMO.get(path)
    if entry is None:
        return None
    if entry[0] != _identity(path):
        del _MEMO[path]
        return None
    _MEMO.move_to_end(path)
    return entry[1]


def _remember(landscape: Landscape) -> Landscape:
    identity = None if landscape.path is None else _identity(landscape.path)
    if identity is None:
        return landscape
    for values in landscape.arrays.values():
        values.flags.writeable = False
    _MEMO[landscape.path] = (identity, landscape)
    _MEMO.move_to_end(landscape.path)
    while len(_MEMO) > 1 and (len(_MEMO) > MEMO_ENTRIES or sum(
            v.nbytes for _, entry in _MEMO.values() for v in entry.arrays.values()) > MEMO_BYTES):
        _MEMO.popitem(last=False)
    return landscape


def _read(key: str, report: bool = True) -> Landscape | None:
    """The memo's or the cache's valid landscape of ``key``, or None (a file that cannot be used
    is reported on stderr when ``report``: it will be swept again)."""
    path = landscape_path(key)
    found = _recall(path)
    if found is not None or not path.exists():
        return found
    try:
        return Landscape.load(path, key)
    except LandscapeError as exc:
        if report:
            print(f"landscape {key}: {exc}; not used (a sweep replaces it)", file=sys.stderr)
        return None


def _lock(key: str) -> FileLock:
    path = landscape_path(key)
    path.parent.mkdir(parents=True, exist_ok=True)
    return FileLock(path.with_name(path.name + ".lock"))


def _cpus(executor: Executor | None, workers: int) -> int:
    if executor is None:
        return workers
    try:  # a Ray executor that is open knows its cluster's CPUs
        return max(1, int(executor.cpus))
    except Exception:
        return max(1, int(getattr(executor, "workers", 1)))


def cached_landscape(evaluator: Evaluator, grid: Grid) -> Landscape | None:
    """The cache's valid landscape of ``evaluator`` on ``grid``, or None; never sweeps (a
    corrupted file is reported on stderr and treated as missing)."""
    found = _read(landscape_key(evaluator, grid))
    return None if found is None else _remember(found)


def landscape_of(evaluator: Evaluator, grid: Grid, *, workers: int = 1,
                 executor: Executor | None = None, progress: bool = True) -> Landscape:
    """The landscape of ``evaluator`` on ``grid``: from the cache, else swept into it.

    Args:
        evaluator: body, task, solver and scoring settings of the worker.
        grid: the locations.
        workers: processes of the local pool that sweeps it (ignored with ``executor``).
        executor: where the chunks run instead (open or not: the local pool, Ray).
        progress: a progress bar of points, with ETA, on stderr.

    Returns:
        The landscape; its ``path`` is the cache file. Memoised in this process.
    """
    check_workers(workers)
    for finished in _landscapes([evaluator], grid, workers, executor, _sweep.CHUNK_POINTS,
                                progress):
        landscape = finished.landscape
    return _remember(landscape)


def landscapes_of(evaluators: Sequence[Evaluator], grid: Grid, *, workers: int = 1,
                  executor: Executor | None = None, chunk: int = CHUNK_POINTS,
                  progress: bool = True) -> Iterator[Finished]:
    """Each evaluator's landscape of ``grid``, from the cache or swept into it.

    Args:
        evaluators: one per worker (the same one twice is swept once).
        grid: the locations, shared by every worker.
        workers: processes of the local pool that sweeps them (ignored with ``executor``).
        executor: where the chunks run instead (open or not: the local pool, Ray).
        chunk: most grid points per task (a lone landscape to compute is cut smaller so that
            every CPU shares it).
        progress: a progress bar of points, with ETA, on stderr.

    Returns:
        An iterator of :class:`Finished` for every evaluator: the cached ones first, then each
        computed one as its last chunk arrives (and those another process was sweeping, once
        it is done). Arguments are checked at the call; the work happens as it is iterated.
    """
    check_chunk(chunk)
    check_workers(workers)
    return _landscapes(list(evaluators), grid, workers, executor, chunk, progress)


def _landscapes(evaluators: Sequence[Evaluator], grid: Grid, workers: int,
                executor: Executor | None, chunk: int, progress: bool) -> Iterator[Finished]:
    """The cached landscapes, then rounds until none is missing: take every missing one's lock
    that is free (without blocking), sweep those together; when all the missing ones are
    locked by other processes, wait for one of them and look again."""
    indices: dict[str, list[int]] = {}
    for i, evaluator in enumerate(evaluators):
        indices.setdefault(landscape_key(evaluator, grid), []).append(i)
    evaluator_of = {key: evaluators[ix[0]] for key, ix in indices.items()}
    todo = []
    for key, ix in indices.items():
        found = _read(key)
        if found is None:
            todo.append(key)
        else:
            yield from (Finished(i, found, True) for i in ix)
    while todo:
        held: dict[str, FileLock] = {}
        busy, later, ready, swept = [], [], [], False
        try:
            for key in todo:
                if len(held) >= MAX_HELD_LOCKS:
                    later.append(key)
                    continue
                lock = _lock(key)
                try:
                    lock.acquire(blocking=False)
                except Timeout:
                    busy.append(key)
                    continue
                found = _read(key, report=False)
                if found is None:
                    held[key] = lock
                else:  # its holder finished it since the first look
                    lock.release()
                    ready.append((key, found))
            if held:
                swept = True
                for key, landscape in _sweep_held(held, evaluator_of, grid, workers, executor,
                                                  chunk, progress):
                    held.pop(key).release()  # before the caller gets it
                    yield from (Finished(i, landscape, False) for i in indices[key])
        finally:
            for lock in held.values():
                lock.release()
        for key, found in ready:
            yield from (Finished(i, found, True) for i in indices[key])
        if busy and not (swept or ready or later):
            print(f"landscape {busy[0]}: another process is sweeping it; waiting",
                  file=sys.stderr, flush=True)
            lock = _lock(busy[0])
            lock.acquire()  # then read it, or sweep it if its holder died, on the next round
            lock.release()
        todo = busy + later


def _sweep_held(held: dict[str, FileLock], evaluator_of: dict[str, Evaluator], grid: Grid,
                workers: int, executor: Executor | None, chunk: int,
                progress: bool) -> Iterator[tuple[str, Landscape]]:
    """Sweep the landscapes whose locks this process holds."""
    started = time.perf_counter()  # a landscape's seconds include preparing its solver
    size = task_points(chunk, grid, len(held), _cpus(executor, workers))
    plans = []
    for key in held:
        output = landscape_path(key)
        for stale in output.parent.glob(f".{output.name}.*.tmp"):  # a save cut by a kill
            stale.unlink(missing_ok=True)
        plans.append(Plan(key, evaluator_of[key], grid, size))
    if executor is None:
        if len(plans) == 1 and plans[0].remaining:  # its warm-start lattice nodes, solved
            # once here before the pool forks, are shared by every process
            posture_solver(plans[0].evaluator, grid.points())
        executor = LocalExecutor(workers)
    for plan, landscape in _sweep.sweep(plans, executor, progress, started):
        yield plan.key, landscape

