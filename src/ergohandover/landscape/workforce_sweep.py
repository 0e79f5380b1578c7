"""The landscapes of many workers on one grid, through any executor (local pool or Ray).

A task is a chunk of (worker, locations): at most ``chunk`` consecutive grid points of one
worker, evaluated where the executor runs it through the one evaluation path
(:func:`~ergohandover.twin.evaluate.evaluate_arrays`) and compacted there, so only the
landscape's small columns travel back. Chunks are gathered as they finish; a worker whose
chunks are all in is written to the landscape cache at once (atomically), under the same key
and with the same arrays as :func:`~ergohandover.landscape.sweep.sweep` would give it. A run
that is killed resumes from the cache: finished workers are read, never recomputed.

A whole 1 cm landscape of the paper-code boundary (92,783 points) is one task by default:
each task solves its worker's warm-start lattice (about 1 s) before its points, so smaller
chunks of one worker would each pay it again on another process.
"""

from __future__ import annotations

import dataclasses
import sys
import time
from collections.abc import Iterator, Sequence
from typing import NamedTuple

import numpy as np
from tqdm import tqdm

from .. import __version__
from ..executor import Executor, LocalExecutor
from ..twin.evaluate import Evaluator, evaluate_arrays
from .cache import Landscape, LandscapeError, landscape_key, landscape_path
from .grid import Grid
from .sweep import ANGLES, SCORES, cached, compact, require_feasible

CHUNK_POINTS = 131_072
"""Grid points per task (a 1 cm paper-code landscape is one task; a 3 mm one is 25)."""
COLUMNS = ("flags", *SCORES, *ANGLES)


class Finished(NamedTuple):
    """One worker's landscape as it arrives: its index in the list given, and whether it was
    read from the cache (``reused``) or computed by this run."""

    index: int
    landscape: Landscape
    reused: bool


def _chunk_job(job: tuple[Evaluator, Grid, int, int]) -> dict[str, np.ndarray]:
    evaluator, grid, start, stop = job
    return compact(evaluate_arrays(grid.points(start, stop), evaluator, columns=COLUMNS))


def sweep_workforce(grid: Grid, evaluators: Sequence[Evaluator],
                    executor: Executor | None = None, chunk: int = CHUNK_POINTS,
                    progress: bool = True) -> Iterator[Finished]:
    """Each worker's landscape of ``grid``, from the cache or swept into it.

    Args:
        grid: the locations, shared by every worker.
        evaluators: one per worker (body, task, solver and scoring settings).
        executor: where the chunks run (default: this process).
        chunk: grid points per task.
        progress: a progress bar of workers, with ETA, on stderr.

    Yields:
        :class:`Finished` for every worker: the cached ones first, then each computed one as
        its last chunk arrives.
    """
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        raise LandscapeError(f"chunk = {chunk!r} is outside the valid range (at least 1)")
    keys = [landscape_key(e, grid) for e in evaluators]
    todo = []
    for i, key in enumerate(keys):
        landscape = cached(key)
        if landscape is None:
            todo.append(i)
        else:
            yield Finished(i, landscape, True)
    if not todo:
        return
    bounds = [(a, min(a + chunk, grid.size)) for a in range(0, grid.size, chunk)]
    jobs = [(evaluators[i], grid, a, b) for i in todo for a, b in bounds]
    owners = [(i, k) for i in todo for k in range(len(bounds))]
    arrived: dict[int, dict[int, dict[str, np.ndarray]]] = {}
    start_time = time.perf_counter()
    bar = tqdm(total=len(evaluators), initial=len(evaluators) - len(todo), unit="worker",
               desc="workforce sweep", file=sys.stderr, disable=not progress)
    try:
        # map_unordered opens the executor for this call unless the caller holds it open.
        for j, part in (executor or LocalExecutor(1)).map_unordered(_chunk_job, jobs):
            i, k = owners[j]
            arrived.setdefault(i, {})[k] = part
            if len(arrived[i]) < len(bounds):
                continue
            parts = arrived.pop(i)
            arrays = {c: np.concatenate([parts[n][c] for n in range(len(bounds))])
                      for c in COLUMNS}
            landscape = Landscape(grid, keys[i], arrays, {
                "evaluator": dataclasses.asdict(evaluators[i]), "version": __version__,
                "points_computed": grid.size,
                "seconds_since_sweep_start": round(time.perf_counter() - start_time, 2)})
            require_feasible(landscape, f" for {evaluators[i].body}")
            landscape.save(landscape_path(keys[i]))
            bar.update(1)
            yield Finished(i, landscape, False)
    finally:
        bar.close()
