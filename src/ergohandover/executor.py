"""Where batched work runs: in this process or chunk by chunk over a pool of worker processes,
behind one interface (:class:`Executor`) that Ray implements too
(:mod:`~ergohandover.study.engines`, where an engine is chosen by name).

The one place that holds a local worker pool. :func:`~ergohandover.twin.evaluate.evaluate_arrays`
(and through it the sweep, the baselines, the participants, the environment's online scores
and the CLI) and the study's agent runs hand it a picklable function and a list of jobs, and
get the results back in job order.

Worker processes are forked, so what the parent prepared before the pool started (the posture
solver's warm-start lattice, compiled kernels) is shared rather than rebuilt. Each worker pins
its BLAS and OpenMP thread pools to one thread: two processes on two cores that each start a
multi-threaded BLAS fight for the cores and run up to 2.5x slower (measured). Work done in this
process is pinned the same way, so that results never depend on the number of workers.
"""

from __future__ import annotations

import functools
import multiprocessing
import os
from collections.abc import Callable, Iterable, Iterator
from contextlib import ExitStack
from typing import Any, Protocol

from threadpoolctl import threadpool_limits

from .errors import ConfigError

THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
"""Read by BLAS and OpenMP when they load: a library a job imports later (torch, for DQN) is
limited by these, as threadpoolctl limits only those already loaded (measured: without them a
DQN run on each of two workers ran 2.1x slower, each torch starting two threads)."""


def pin_threads() -> None:
    """Limit BLAS and OpenMP in this process to one thread (a worker's initialiser): those
    loaded now, and those a job loads later."""
    os.environ.update(dict.fromkeys(THREAD_VARIABLES, "1"))
    threadpool_limits(limits=1)


class Executor(Protocol):
    """Runs ``func(job)`` for a list of jobs somewhere, as a context manager that holds its
    workers between calls."""

    def __enter__(self) -> Executor: ...

    def __exit__(self, *exc) -> None: ...

    def map(self, func: Callable[[Any], Any], jobs: Iterable[Any]) -> Iterator[Any]:
        """``func(job)`` for every job, yielded in job order."""
        ...

    def map_unordered(self, func: Callable[[Any], Any],
                      jobs: Iterable[Any]) -> Iterator[tuple[int, Any]]:
        """``(index, func(jobs[index]))`` for every job, as each finishes."""
        ...


def _indexed(func: Callable[[Any], Any], item: tuple[int, Any]) -> tuple[int, Any]:
    index, job = item
    return index, func(job)


def check_workers(workers: int) -> int:
    """``workers`` if it is a whole number of at least 1; a one-line ConfigError otherwise."""
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ConfigError(f"workers = {workers!r} is outside the valid range (at least 1)")
    return workers


class LocalExecutor:
    """Runs jobs in this process (``workers=1``) or over a fork pool of ``workers`` processes.

    Use it as a context manager to keep one pool over several :meth:`map` calls (the sweep's
    checkpointed parts); :meth:`map` outside a ``with`` block opens and closes a pool itself.

    Args:
        workers: processes; 1 runs every job in this process (unless ``isolated``).
        isolated: run every job in a new (forked) process of its own, also with one worker:
            for work that depends on process-wide state set once (OMPL's random seed), which
            this process must then not have set itself.
    """

    def __init__(self, workers: int = 1, isolated: bool = False):
        self.workers = check_workers(workers)
        self.isolated = isolated
        self._pool = None
        self._stack: ExitStack | None = None

    def __enter__(self) -> LocalExecutor:
        self._stack = ExitStack()
        # This process too: a short job list runs here, with the same arithmetic as a worker.
        self._stack.enter_context(threadpool_limits(limits=1))
        if self.workers > 1 or self.isolated:
            self._pool = self._stack.enter_context(multiprocessing.get_context("fork").Pool(
                self.workers, initializer=pin_threads,
                maxtasksperchild=1 if self.isolated else None))
        return self

    def __exit__(self, *exc) -> None:
        assert self._stack is not None
        self._stack.close()
        self._pool, self._stack = None, None

    def map(self, func: Callable[[Any], Any], jobs: Iterable[Any]) -> Iterator[Any]:
        """``func(job)`` for every job, yielded in job order as each finishes."""
        jobs = list(jobs)
        if self._stack is None:
            with self:
                yield from self.map(func, jobs)
            return
        if self._pool is None or (len(jobs) < 2 and not self.isolated):
            yield from map(func, jobs)
        else:
            yield from self._pool.imap(func, jobs)

    def map_unordered(self, func: Callable[[Any], Any],
                      jobs: Iterable[Any]) -> Iterator[tuple[int, Any]]:
        """``(index, func(jobs[index]))`` for every job, as each finishes (one job at a time
        per worker, so a long job list streams out evenly)."""
        jobs = list(jobs)
        if self._stack is None:
            with self:
                yield from self.map_unordered(func, jobs)
            return
        if self._pool is None or (len(jobs) < 2 and not self.isolated):
            yield from ((i, func(job)) for i, job in enumerate(jobs))
        else:
            yield from self._pool.imap_unordered(functools.partial(_indexed, func),
                                                 enumerate(jobs))
