"""The one sweep: the landscapes of one or many workers on one grid, chunk by chunk, through any
executor (this process, the local pool, Ray).

A task is a chunk ``(evaluator, grid, start, stop)`` of at most ``chunk`` consecutive grid
points, evaluated where the executor runs it through the one evaluation path
(:func:`~ergohandover.twin.evaluate.evaluate_arrays`) and compacted there, so only the
landscape's small columns travel back. Each finished chunk is written atomically into the
landscape's ``<key>.npz.parts/`` folder beside the cache file, so a sweep killed at any moment
(even kill -9) resumes without redoing finished chunks, whatever chunk size either run used.
When a landscape's chunks are all in, :meth:`Plan.finish` assembles it with one set of metadata,
checks it has a feasible point, saves it atomically and removes its parts.

Nothing here guards against two processes sweeping one landscape: the caller holds the
landscape's lock (:mod:`~ergohandover.landscape.store`, the only caller).
"""

from __future__ import annotations

import dataclasses
import math
import shutil
import sys
import time
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np
from tqdm import tqdm

from .. import __version__
from ..errors import ErgohandoverError
from ..executor import Executor
from ..io.atomic import atomic_write
from ..twin.evaluate import Evaluator, evaluate_arrays
from .cache import Landscape, LandscapeError, landscape_path
from .grid import Grid

SCORES = ("paper_postural", "reba", "reba_ab", "rula", "reba_table_a", "reba_table_b",
          "reba_score_a", "reba_score_b")
ANGLES = ("trunk_flexion", "trunk_side_bend", "trunk_twist", "neck_flexion",
          "left_knee_flexion", "left_upper_arm_flexion", "right_upper_arm_flexion",
          "left_elbow_flexion", "right_elbow_flexion", "hand_error_m")
COLUMNS = ("flags", *SCORES, *ANGLES)
CHUNK_POINTS = 524_288
"""Most grid points per task: a fraction of a minute of one core, so a killed sweep loses
little; a whole 1 cm paper-code landscape (92,783 points) of one worker of a workforce is one
task, because each process that evaluates a worker first solves that worker's warm-start
lattice; and a task of the fine warm start solves the lattice nodes of its thin slab of
the grid, of which those on the slab's faces again in the next task (on the 3 mm paper grid,
0.24 nodes per point in tasks of 100,000 points, 0.15 in tasks of 400,000)."""
MIN_TASK_POINTS = 2_048
TASKS_PER_CPU = 4
"""A lone landscape is cut into about this many tasks per CPU (never fewer than
:data:`MIN_TASK_POINTS` points, never more than the chunk), so every CPU has work to the end."""
STOP_AFTER_CHUNKS: int | None = None
"""Test hook: stop (raising :class:`SweepInterrupted`) after computing this many chunks."""


class SweepInterrupted(ErgohandoverError, RuntimeError):
    """The sweep stopped early by :data:`STOP_AFTER_CHUNKS`, as a kill would (tests only)."""


def compact(rows: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The landscape's columns of evaluated rows: int8 scores (-1 infeasible), float32 angles."""
    flags = rows["flags"]
    out = {"flags": flags}
    for name in SCORES:
        out[name] = np.where(flags == 0, rows[name], -1).astype(np.int8)
    for name in ANGLES:
        out[name] = rows[name].astype(np.float32)
    return out


def check_chunk(chunk: int) -> int:
    """``chunk`` if it is a whole number of at least 1; a one-line LandscapeError otherwise."""
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        raise LandscapeError(f"chunk = {chunk!r} is outside the valid range (at least 1)")
    return chunk


def task_points(chunk: int, grid: Grid, landscapes: int, cpus: int) -> int:
    """Points per task: ``chunk``, or less for a lone landscape so that all CPUs share it."""
    if landscapes != 1:
        return chunk
    return min(chunk, max(MIN_TASK_POINTS, math.ceil(grid.size / (TASKS_PER_CPU * cpus))))


def whose(evaluator: Evaluator) -> str:
    """The worker of an evaluator, for messages."""
    body = evaluator.body
    return f"{body.sex}, {body.stature_m:g} m, {body.mass_kg:g} kg"


def require_feasible(landscape: Landscape, worker: str = "") -> None:
    """A one-line LandscapeError when no point of the landscape is feasible."""
    if not landscape.feasible.any():
        raise LandscapeError(f"no feasible point in the boundary ({landscape.grid.describe()})"
                             f"{f' for the worker ({worker})' if worker else ''}: every location "
                             "is out of reach, inside the body or unbalanced")


def parts_folder(key: str) -> Path:
    """Where the finished chunks of the landscape ``key`` wait while it is being swept."""
    path = landscape_path(key)
    return path.with_name(path.name + ".parts")


def _evaluate_chunk(job: tuple[Evaluator, Grid, int, int]) -> dict[str, np.ndarray]:
    evaluator, grid, start, stop = job
    return compact(evaluate_arrays(grid.points(start, stop), evaluator, columns=COLUMNS))


def _read_part(path: Path, size: int) -> dict[str, np.ndarray] | None:
    try:
        with np.load(path) as data:
            part = {name: data[name] for name in COLUMNS}
        return part if all(len(v) == size for v in part.values()) else None
    except Exception:  # a part that cannot be read is simply computed again
        return None


class Plan:
    """One landscape being swept: its chunks already in its parts folder (from a run that was
    killed), the ranges still missing, cut into tasks of at most ``chunk`` points."""

    def __init__(self, key: str, evaluator: Evaluator, grid: Grid, chunk: int):
        self.key, self.evaluator, self.grid = key, evaluator, grid
        self.folder = parts_folder(key)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.parts: dict[int, dict[str, np.ndarray]] = {}  # start -> columns
        covered = 0
        for path in sorted(self.folder.glob("chunk_*_*.npz")):
            bounds = path.stem.split("_")[1:]
            if len(bounds) != 2 or not all(n.isdigit() for n in bounds):
                continue  # not a part's name
            start, stop = int(bounds[0]), int(bounds[1])
            if start < covered or stop > grid.size or stop <= start:
                continue  # overlaps a part kept already, or belongs to no chunk of this grid
            part = _read_part(path, stop - start)
            if part is not None:
                self.parts[start] = part
                covered = stop
        edges = sorted((s, s + len(p["flags"])) for s, p in self.parts.items())
        gaps, at = [], 0
        for start, stop in [*edges, (grid.size, grid.size)]:
            gaps += [(a, min(a + chunk, start)) for a in range(at, start, chunk)]
            at = stop
        self.missing = gaps
        self.remaining = len(gaps)
        self.computed = 0

    def store(self, start: int, stop: int, part: dict[str, np.ndarray]) -> None:
        """Keep a finished chunk, on disk first (atomically) so a kill cannot lose it."""
        atomic_write(self.folder / f"chunk_{start:010d}_{stop:010d}.npz",
                     lambda h: np.savez(h, **part), binary=True)
        self.parts[start] = part
        self.computed += stop - start
        self.remaining -= 1

    def finish(self, seconds: float) -> Landscape:
        """The landscape of all the chunks: checked, saved into the cache, parts removed."""
        order = sorted(self.parts)
        arrays = {c: np.concatenate([self.parts[s][c] for s in order]) for c in COLUMNS}
        assert len(arrays["flags"]) == self.grid.size, "a landscape's chunks must tile its grid"
        landscape = Landscape(self.grid, self.key, arrays, {
            "evaluator": dataclasses.asdict(self.evaluator), "version": __version__,
            "points_computed": self.computed, "seconds": round(seconds, 2)})
        if not landscape.feasible.any():  # not worth resuming either
            shutil.rmtree(self.folder, ignore_errors=True)
            require_feasible(landscape, whose(self.evaluator))
        landscape.save(landscape_path(self.key))
        shutil.rmtree(self.folder, ignore_errors=True)
        self.parts.clear()
        return landscape


def sweep(plans: Sequence[Plan], executor: Executor, progress: bool = True,
          started: float | None = None) -> Iterator[tuple[Plan, Landscape]]:
    """Compute the missing chunks of every plan through ``executor`` (opened for this call
    unless the caller holds it open), yielding each landscape as its last chunk arrives (those
    with nothing missing first).

    Seconds in a landscape's metadata count from ``started`` (``time.perf_counter()``; default:
    the start of this call) to its assembly.
    """
    start_time = time.perf_counter() if started is None else started
    for plan in plans:
        if plan.remaining == 0:  # killed after its last chunk was written, before the save
            yield plan, plan.finish(time.perf_counter() - start_time)
    jobs = [(plan.evaluator, plan.grid, a, b) for plan in plans for a, b in plan.missing]
    owners = [plan for plan in plans for _ in plan.missing]
    stopped = STOP_AFTER_CHUNKS is not None and len(jobs) > STOP_AFTER_CHUNKS
    if stopped:
        jobs = jobs[:STOP_AFTER_CHUNKS]
    if not jobs:
        return
    desc = "sweep" if len(plans) == 1 else f"sweep of {len(plans)} landscapes"
    bar = tqdm(total=sum(b - a for _, _, a, b in jobs), unit="pt", unit_scale=True, desc=desc,
               file=sys.stderr, disable=not progress)
    try:
        for j, part in executor.map_unordered(_evaluate_chunk, jobs):
            plan, (_, _, a, b) = owners[j], jobs[j]
            plan.store(a, b, part)
            bar.update(b - a)
            if plan.remaining == 0:
                yield plan, plan.finish(time.perf_counter() - start_time)
    finally:
        bar.close()
    if stopped:
        raise SweepInterrupted(f"stopped after {STOP_AFTER_CHUNKS} chunks")
