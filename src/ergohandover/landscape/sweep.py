"""The exhaustive landscape: every grid point evaluated once, kept in the landscape cache.

The sweep runs in parts; each finished part is written (atomically) beside the cache file, so a
sweep killed at any moment resumes without redoing finished parts and yields the same file.
Every point goes through :func:`~ergohandover.twin.evaluate.evaluate_stream`, the one
evaluation path, on one pool of worker processes kept for the whole sweep.
"""

from __future__ import annotations

import dataclasses
import shutil
import sys
import time

import numpy as np
from tqdm import tqdm

from .. import __version__
from ..executor import LocalExecutor
from ..io.atomic import atomic_write
from ..twin.evaluate import CHUNK, Evaluator, evaluate_stream, posture_solver
from .cache import Landscape, LandscapeError, landscape_key, landscape_path
from .grid import Grid

__all__ = ["ANGLES", "SCORES", "Landscape", "LandscapeError", "sweep"]

SCORES = ("paper_postural", "reba", "reba_ab", "rula", "reba_table_a", "reba_table_b",
          "reba_score_a", "reba_score_b")
ANGLES = ("trunk_flexion", "trunk_side_bend", "trunk_twist", "neck_flexion",
          "left_knee_flexion", "left_upper_arm_flexion", "right_upper_arm_flexion",
          "left_elbow_flexion", "right_elbow_flexion", "hand_error_m")
PART = 65_536  # points per checkpointed part (a few seconds on two cores)


def compact(rows: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The landscape's columns of evaluated rows: int8 scores (-1 infeasible), float32 angles."""
    flags = rows["flags"]
    out = {"flags": flags}
    for name in SCORES:
        out[name] = np.where(flags == 0, rows[name], -1).astype(np.int8)
    for name in ANGLES:
        out[name] = rows[name].astype(np.float32)
    return out


def _load_part(path, size: int) -> dict[str, np.ndarray] | None:
    try:
        with np.load(path) as data:
            part = {name: data[name] for name in data.files}
        return part if all(len(v) == size for v in part.values()) else None
    except Exception:  # a part cut short by a kill is simply redone
        return None


def _save_part(path, part: dict[str, np.ndarray]) -> None:
    atomic_write(path, lambda h: np.savez(h, **part), binary=True)


def cached(key: str) -> Landscape | None:
    """The cache's landscape of ``key``, or None when there is none or it cannot be used (a
    corrupted or mismatched file is reported and will be recomputed)."""
    path = landscape_path(key)
    if not path.exists():
        return None
    try:
        return Landscape.load(path, key)
    except LandscapeError as exc:
        print(f"recomputing: {exc}", file=sys.stderr)
        return None


def require_feasible(landscape: Landscape, whose: str = "") -> None:
    """A one-line LandscapeError when no point of the landscape is feasible."""
    if not landscape.feasible.any():
        raise LandscapeError(f"no feasible point in the boundary ({landscape.grid.describe()})"
                             f"{whose}: every location is out of reach, inside the body or "
                             "unbalanced")


def sweep(grid: Grid, evaluator: Evaluator | None = None, workers: int = 1,
          progress: bool = True, stop_after_parts: int | None = None,
          ) -> tuple[Landscape | None, bool]:
    """The landscape of ``grid``: from the cache if a valid file is there, else swept into it.

    Args:
        grid: the locations.
        evaluator: body, task, solver and scoring settings (default: all defaults).
        workers: processes.
        progress: show a progress bar with ETA on stderr.
        stop_after_parts: stop (unfinished, returning None) after computing this many parts;
            for tests of resumption.

    Returns:
        The landscape and whether it was reused from the cache unchanged.
    """
    evaluator = evaluator or Evaluator()
    key = landscape_key(evaluator, grid)
    output = landscape_path(key)
    landscape = cached(key)
    if landscape is not None:
        return landscape, True
    parts_dir = output.with_name(output.name + ".parts")
    if (parts_dir / "key").exists() and (parts_dir / "key").read_text() != key:
        shutil.rmtree(parts_dir)
    parts_dir.mkdir(parents=True, exist_ok=True)
    (parts_dir / "key").write_text(key)
    bounds = [(a, min(a + PART, grid.size)) for a in range(0, grid.size, PART)]
    done = {i: _load_part(parts_dir / f"part_{i:05d}.npz", b - a)
            for i, (a, b) in enumerate(bounds)}
    done = {i: part for i, part in done.items() if part is not None}
    start_time = time.perf_counter()
    computed = 0
    bar = tqdm(total=grid.size, initial=sum(bounds[i][1] - bounds[i][0] for i in done),
               unit="pt", unit_scale=True, desc="sweep", file=sys.stderr, disable=not progress)
    columns = ("flags", *SCORES, *ANGLES)
    pending = [i for i in range(len(bounds)) if i not in done]
    stopped = stop_after_parts is not None and len(pending) > stop_after_parts
    if stopped:
        pending = pending[:stop_after_parts]
    # Every chunk of every missing part is queued at once: the workers keep evaluating while
    # this process stores each part as its last chunk arrives.
    batches, owners = [], []
    for i in pending:
        a, b = bounds[i]
        points = grid.points(a, b)
        for c in range(0, b - a, CHUNK):
            batches.append(points[c:c + CHUNK])
            owners.append(i)
    arrived: dict[int, list[dict[str, np.ndarray]]] = {}
    posture_solver(evaluator)  # the warm-start lattice, prepared once before the pool forks
    try:
        with LocalExecutor(workers) as executor:
            for i, rows in zip(owners, evaluate_stream(batches, evaluator, columns,
                                                       executor=executor), strict=True):
                bar.update(len(rows["flags"]))
                arrived.setdefault(i, []).append(rows)
                a, b = bounds[i]
                if sum(len(r["flags"]) for r in arrived[i]) < b - a:
                    continue
                chunks = arrived.pop(i)
                part = compact({c: np.concatenate([r[c] for r in chunks]) for c in columns})
                _save_part(parts_dir / f"part_{i:05d}.npz", part)
                done[i] = part
                computed += b - a
    finally:
        bar.close()
    if stopped:
        return None, False
    arrays = {name: np.concatenate([done[i][name] for i in range(len(bounds))])
              for name in done[0]}
    elapsed = time.perf_counter() - start_time
    landscape = Landscape(grid, key, arrays, {
        "evaluator": dataclasses.asdict(evaluator), "version": __version__,
        "points_computed": computed, "seconds": round(elapsed, 2)})
    if not landscape.feasible.any():
        shutil.rmtree(parts_dir)
    require_feasible(landscape)
    landscape.save(output)
    shutil.rmtree(parts_dir)
    return landscape, False
