"""The engines a study part can run on, chosen by name: this machine's process pool, or Ray
(jobs become Ray tasks on a new local instance or on a running cluster).

:class:`RayExecutor` has the interface of :class:`~ergohandover.executor.LocalExecutor`
(``map`` in job order, ``map_unordered`` as tasks finish), so a caller moves from one machine
to a cluster by changing the engine, not its code. Ray is an optional dependency (``pip install -e
".[cluster]"``), imported only here and only when a Ray executor is opened.

Each task pins BLAS and OpenMP to one thread, as the local pool's workers do, so that a
result never depends on where it was computed. On a cluster every node must have this package
installed (the tasks import it by name).
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from typing import Any

from ..errors import ConfigError
from ..executor import Executor, LocalExecutor, check_workers, keep_signal_handlers, pin_threads

ENGINES = ("local", "ray")
"""Where work can run: this machine's process pool, or Ray (a local instance or a cluster)."""
INSTALL_HINT = 'pip install -e ".[cluster]"'


def make_executor(engine: str = "local", workers: int = 1, address: str | None = None,
                  isolated: bool = False) -> Executor:
    """The executor of an engine: ``local`` (a process pool of ``workers``) or ``ray`` (a new
    local Ray instance of ``workers`` CPUs, or the running cluster at ``address``: ``auto`` or
    ``HOST:PORT``); ``isolated``: every job in a fresh process of its own (for work that sets
    process-wide state once, such as OMPL's seed). Every value is checked here; Ray is imported
    only when it is opened."""
    if engine not in ENGINES:
        raise ConfigError(f"engine = {engine!r} is not allowed (use "
                          f"{' or '.join(map(repr, ENGINES))})")
    if engine == "local":
        if address is not None:
            raise ConfigError(f"address = {address!r} needs engine = 'ray' (the local pool "
                              "has no address)")
        return LocalExecutor(workers, isolated=isolated)
    return RayExecutor(workers, address, isolated=isolated)


@dataclass(frozen=True)
class Engine:
    """Where a study's independent jobs run: its name (``local`` or ``ray``), the processes or
    CPUs of a local run and a Ray cluster's address. Checked when made; each part opens its own
    executor from it (:meth:`executor`), so one engine serves the whole study."""

    name: str = "local"
    workers: int = 1
    address: str | None = None

    def __post_init__(self):
        make_executor(self.name, self.workers, self.address)  # every value checked here

    def executor(self, isolated: bool = False) -> Executor:
        """A new executor of this engine (open it with ``with``)."""
        return make_executor(self.name, self.workers, self.address, isolated)

    def session(self):
        """A context that keeps the engine up across parts: Ray is started (or joined) once,
        and every executor opened inside uses it; the local pool needs nothing."""
        return self.executor() if self.name == "ray" else contextlib.nullcontext()


def _pinned(func: Callable[[Any], Any], job: Any) -> Any:
    """``func(job)`` with BLAS and OpenMP limited to one thread, also in libraries the job loads
    (the body of every task: a Ray worker process is pinned as a pool worker is)."""
    pin_threads()
    return func(job)


def check_address(address: str | None) -> str | None:
    """``None``, ``auto`` or ``HOST:PORT``; a one-line ConfigError otherwise."""
    if address is None or address == "auto":
        return address
    host, _, port = address.rpartition(":")
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise ConfigError(f"address = {address!r} is not valid (use auto or HOST:PORT, "
                          "e.g. 10.0.0.5:6379)")
    return address


class RayExecutor:
    """Runs jobs as Ray tasks of one CPU each.

    Args:
        workers: CPUs of the local Ray instance started when there is no ``address`` (ignored
            when joining a cluster, whose own CPUs are used).
        address: ``auto`` (the cluster this machine belongs to) or ``HOST:PORT`` of a running
            cluster's head; ``None`` starts a local instance and stops it on exit (unless Ray
            was already running in this process: then it is used and left running).
        isolated: a worker process of its own for every task (Ray's ``max_calls=1``).
    """

    def __init__(self, workers: int = 1, address: str | None = None, isolated: bool = False):
        self.workers = check_workers(workers)
        self.address = check_address(address)
        self.isolated = isolated
        self._ray = None
        self._remote = None
        self._started = False

    def __enter__(self) -> RayExecutor:
        try:
            import ray
        except ImportError:
            raise ConfigError(f"engine = 'ray' needs Ray, which is not installed "
                              f"({INSTALL_HINT})") from None
        self._ray = ray
        if not ray.is_initialized():
            options = {"include_dashboard": False, "log_to_driver": False,
                       "logging_level": logging.WARNING}
            # ray.init installs a SIGTERM handler that exits at once; the caller's (which
            # unwinds, so that the instance is shut down and staged folders removed) is kept.
            with keep_signal_handlers():
                if self.address is None:
                    ray.init(num_cpus=self.workers, **options)
                else:
                    try:
                        ray.init(address=self.address, **options)
                    except ConnectionError as exc:
                        raise ConfigError(f"address = {self.address!r}: no Ray cluster "
                                          f"answers there ({str(exc).splitlines()[0]})") from None
            self._started = True
        self._remote = ray.remote(num_cpus=1, max_calls=1 if self.isolated else 0)(_pinned)
        return self

    def __exit__(self, *exc) -> None:
        if self._started:
            self._ray.shutdown()
        self._ray, self._remote, self._started = None, None, False

    @property
    def cpus(self) -> int:
        """CPUs of the instance or cluster this executor runs on."""
        return int(self._ray.cluster_resources().get("CPU", 0))

    def _submit(self, func: Callable[[Any], Any], jobs: Iterable[Any]) -> list:
        func_ref = self._ray.put(func)  # shipped once, not with every task
        return [self._remote.remote(func_ref, job) for job in jobs]

    def map(self, func: Callable[[Any], Any], jobs: Iterable[Any]) -> Iterator[Any]:
        """``func(job)`` for every job, yielded in job order (all submitted at once)."""
        if self._ray is None:
            with self:
                yield from self.map(func, jobs)
            return
        for ref in self._submit(func, jobs):
            yield self._ray.get(ref)

    def map_unordered(self, func: Callable[[Any], Any],
                      jobs: Iterable[Any]) -> Iterator[tuple[int, Any]]:
        """``(index, func(jobs[index]))`` for every job, as each task finishes."""
        if self._ray is None:
            with self:
                yield from self.map_unordered(func, jobs)
            return
        refs = self._submit(func, jobs)
        index = {ref: i for i, ref in enumerate(refs)}
        pending = list(refs)
        while pending:
            done, pending = self._ray.wait(pending, num_returns=1)
            yield index[done[0]], self._ray.get(done[0])
