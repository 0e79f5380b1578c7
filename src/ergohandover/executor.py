"""Where batched work runs: in this process or chunk by chunk over a pool of worker processes,
behind one interface (:class:`Executor`) that Ray implements too
(:mod:`~ergohandover.study.engines`, where an engine is chosen by name).

The one place that holds a local worker pool. :func:`~ergohandover.twin.evaluate.evaluate_arrays`
(and through it the sweep, the baselines, the participants, the environment's online scores
and the CLI) and the study's agent runs hand it a picklable function and a list of jobs, and
get the results back in job order.

Worker processes are forked, so what the parent prepared before the pool started (the posture
solver's warm-start lattice nodes, compiled kernels) is shared rather than rebuilt. Each worker pins
its BLAS and OpenMP thread pools to one thread: two processes on two cores that each start a
multi-threaded BLAS fight for the cores and run up to 2.5x slower (measured). Work done in this
process is pinned the same way, so that results never depend on the number of workers.

How work stops: Python stops at Ctrl-C (SIGINT) by raising KeyboardInterrupt, which unwinds every
``with`` block: a pool terminates its workers, Ray shuts its instance down, the study removes its
staged part folders (:func:`~ergohandover.study.resume.run_part`). ``kill`` (SIGTERM) would end
the process at once and leave its workers running with no parent; :func:`clean_stop` turns it
into the same KeyboardInterrupt. Workers ignore SIGINT — a Ctrl-C in a terminal reaches the
whole process group, and the parent alone decides how to stop — and die at SIGTERM, which is
how a pool terminates them.
"""

from __future__ import annotations

import functools
import multiprocessing
import os
import signal
import sys
from collections.abc import Callable, Iterable, Iterator
from contextlib import ExitStack, contextmanager, suppress
from pathlib import Path
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


EXIT_CODES = {signal.SIGINT: 130, signal.SIGTERM: 143}
"""The shell's convention: 128 + the signal's number."""


class Stopped(KeyboardInterrupt):
    """Raised in the main process by SIGTERM (a KeyboardInterrupt, so that everything that
    cleans up after Ctrl-C cleans up after ``kill`` too)."""

    signal_number = signal.SIGTERM


_RECEIVED: list[int] = []
"""The signals that stopped this process (a library may re-raise a KeyboardInterrupt of its own
in place of :class:`Stopped`, as Ray's waits do)."""


_MAIN: list[int] = []
"""The process that installed the handler: a pool's worker forked from it holds the handler too
until its initialiser runs, and a pool may terminate it in that moment."""


def _raise_stopped(signum, frame) -> None:
    if _MAIN and os.getpid() != _MAIN[-1]:  # a just-forked worker: die as SIGTERM would
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        return
    _RECEIVED.append(signum)
    raise Stopped()


def stop_on_signals() -> None:
    """Make SIGTERM raise :class:`Stopped` in this (main) process; SIGINT keeps raising
    KeyboardInterrupt. Only the main thread can install handlers: elsewhere this does
    nothing."""
    with suppress(ValueError):  # not the main thread (e.g. a test runner's worker thread)
        _MAIN.append(os.getpid())
        signal.signal(signal.SIGTERM, _raise_stopped)
        signal.signal(signal.SIGINT, signal.default_int_handler)


def worker_signals() -> None:
    """A worker process's handlers: SIGINT ignored (its parent stops it), SIGTERM fatal."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


@contextmanager
def keep_signal_handlers() -> Iterator[None]:
    """Restore SIGINT's and SIGTERM's handlers after the block (a library that installs its
    own, such as Ray's ``init``, does not take over how this program stops)."""
    saved = {number: signal.getsignal(number) for number in EXIT_CODES}
    try:
        yield
    finally:
        for number, handler in saved.items():
            # not the main thread (ValueError), or a handler set in C (None: TypeError)
            with suppress(ValueError, TypeError):
                signal.signal(number, handler)


@contextmanager
def clean_stop(resumes: bool = False, name: str | None = None) -> Iterator[None]:
    """Run a command's body with :func:`stop_on_signals`; on SIGINT or SIGTERM print one line
    and exit with the shell's code for the signal (130 or 143), after every ``with`` block
    inside has cleaned up (the handlers in place before are restored after).

    Args:
        resumes: say that a rerun resumes where this one stopped (the study's scripts).
        name: how the line names the program (default: the script's name).
    """
    _RECEIVED.clear()
    try:
        with keep_signal_handlers():  # the caller's handlers are back afterwards
            stop_on_signals()
            yield
    except KeyboardInterrupt as exc:
        number = _RECEIVED[-1] if _RECEIVED else getattr(exc, "signal_number", signal.SIGINT)
        # A command that said what it kept (a session's saved trials) says it in this line.
        then = getattr(exc, "kept", None) or (
            "; finished parts are kept and a rerun resumes" if resumes else
            "; nothing half-written was kept")
        print(f"{name or Path(sys.argv[0]).stem}: stopped by {signal.Signals(number).name}"
              f"{then}", file=sys.stderr)
        sys.exit(EXIT_CODES[number])


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


def init_worker() -> None:
    """A pool worker's start: one BLAS thread, and signals left to the parent (a Ctrl-C stops
    the parent, which then terminates its pool; see :mod:`~ergohandover.stopping`)."""
    worker_signals()
    pin_threads()


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
                self.workers, initializer=init_worker,
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
