"""The exhaustive landscape: every grid point evaluated once, kept in a compact, checked file.

The sweep runs in parts; each finished part is written (atomically) beside the output, so a
sweep killed at any moment resumes without redoing finished parts and yields the same file.
The file is keyed by a hash of everything that determines its content (body, task, boundary,
step, solver and scoring settings, package version); a file whose key does not match, or whose
checksum fails, is recomputed, never used.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import multiprocessing
import shutil
import sys
import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

from .. import __version__
from ..io.atomic import atomic_write
from ..twin.evaluate import CHUNK, Evaluator, _evaluate_chunk, posture_solver
from ..twin.task import Boundary
from .grid import Grid

SCORES = ("paper_postural", "reba", "reba_ab", "rula", "reba_table_a", "reba_table_b",
          "reba_score_a", "reba_score_b")
ANGLES = ("trunk_flexion", "trunk_side_bend", "trunk_twist", "neck_flexion",
          "left_knee_flexion", "left_upper_arm_flexion", "right_upper_arm_flexion",
          "left_elbow_flexion", "right_elbow_flexion", "hand_error_m")
PART = 65_536  # points per checkpointed part (~6 s on two cores)


class LandscapeError(ValueError):
    """A landscape that cannot be built or used; the message is one line."""


def landscape_key(evaluator: Evaluator, grid: Grid) -> str:
    """A hash of everything that determines a landscape's content."""
    spec = {"evaluator": dataclasses.asdict(evaluator), "grid": dataclasses.asdict(grid),
            "version": __version__}
    return hashlib.sha256(json.dumps(spec, sort_keys=True).encode()).hexdigest()[:16]


def _checksum(arrays: dict[str, np.ndarray]) -> str:
    digest = hashlib.sha256()
    for name in sorted(arrays):
        digest.update(name.encode())
        digest.update(np.ascontiguousarray(arrays[name]).tobytes())
    return digest.hexdigest()


@dataclasses.dataclass
class Landscape:
    """Compact per-point results in grid order (flat, C order: x slowest).

    ``arrays``: ``flags`` (uint8 bit mask of :data:`evaluate.REASONS`, 0 = feasible), each of
    :data:`SCORES` as int8 (-1 where infeasible) and each of :data:`ANGLES` as float32 [deg, m].
    """

    grid: Grid
    key: str
    arrays: dict[str, np.ndarray]
    meta: dict

    @property
    def feasible(self) -> np.ndarray:
        return self.arrays["flags"] == 0

    def save(self, path: Path) -> Path:
        meta = {**self.meta, "key": self.key, "checksum": _checksum(self.arrays),
                "grid": dataclasses.asdict(self.grid)}
        return atomic_write(path, lambda h: np.savez_compressed(
            h, meta=np.array(json.dumps(meta)), **self.arrays), binary=True)

    @classmethod
    def load(cls, path: Path, key: str | None = None) -> Landscape:
        """Read and verify a landscape; LandscapeError if unreadable, corrupted or mismatched."""
        try:
            with np.load(path) as data:
                meta = json.loads(str(data["meta"]))
                arrays = {name: data[name] for name in data.files if name != "meta"}
        except Exception as exc:  # any unreadable file is a corrupted one
            raise LandscapeError(f"{path} is not a readable landscape ({type(exc).__name__})") \
                from None
        if key is not None and meta.get("key") != key:
            raise LandscapeError(f"{path} was made with other settings (key {meta.get('key')}, "
                                 f"expected {key})")
        if meta.get("checksum") != _checksum(arrays):
            raise LandscapeError(f"{path} is corrupted (checksum mismatch)")
        g = meta["grid"]
        grid = Grid(Boundary(tuple(g["boundary"]["x"]), tuple(g["boundary"]["y"]),
                             tuple(g["boundary"]["z"]), g["boundary"]["name"]), g["step"])
        return cls(grid, meta["key"], arrays, meta)


def _compact(evaluator: Evaluator, grid: Grid, start: int, stop: int) -> dict[str, np.ndarray]:
    """Evaluate points ``start:stop`` of the grid and keep the compact columns."""
    rows = _evaluate_chunk(evaluator, grid.points(start, stop))
    flags = rows["flags"]
    out = {"flags": flags}
    for name in SCORES:
        out[name] = np.where(flags == 0, rows[name], -1).astype(np.int8)
    for name in ANGLES:
        out[name] = rows[name].astype(np.float32)
    return out


def _run(job):
    return _compact(*job)


def _load_part(path: Path, size: int) -> dict[str, np.ndarray] | None:
    try:
        with np.load(path) as data:
            part = {name: data[name] for name in data.files}
        return part if all(len(v) == size for v in part.values()) else None
    except Exception:  # a part cut short by a kill is simply redone
        return None


def _save_part(path: Path, part: dict[str, np.ndarray]) -> None:
    atomic_write(path, lambda h: np.savez(h, **part), binary=True)


def sweep(grid: Grid, evaluator: Evaluator, output: Path, workers: int = 1,
          progress: bool = True, stop_after_parts: int | None = None) -> tuple[Landscape, bool]:
    """Evaluate every grid point, resuming from finished parts; reuse a matching file.

    Args:
        grid: the locations.
        evaluator: body, task, solver and scoring settings.
        output: the landscape file (``.npz``); parts go to ``<output>.parts/`` meanwhile.
        workers: processes.
        progress: show a progress bar with ETA on stderr.
        stop_after_parts: stop (unfinished) after computing this many parts; for tests of
            resumption.

    Returns:
        The landscape and whether it was reused from ``output`` unchanged.
    """
    key = landscape_key(evaluator, grid)
    if output.exists():
        try:
            return Landscape.load(output, key), True
        except LandscapeError as exc:
            print(f"recomputing: {exc}", file=sys.stderr)
    parts_dir = output.with_name(output.name + ".parts")
    if (parts_dir / "key").exists() and (parts_dir / "key").read_text() != key:
        shutil.rmtree(parts_dir)
    parts_dir.mkdir(parents=True, exist_ok=True)
    (parts_dir / "key").write_text(key)
    bounds = [(a, min(a + PART, grid.size)) for a in range(0, grid.size, PART)]
    done = {i: _load_part(parts_dir / f"part_{i:05d}.npz", b - a)
            for i, (a, b) in enumerate(bounds)}
    done = {i: part for i, part in done.items() if part is not None}
    posture_solver(evaluator)  # the warm-start lattice, solved once before forking
    start_time = time.perf_counter()
    computed, parts_computed = 0, 0
    bar = tqdm(total=grid.size, initial=sum(bounds[i][1] - bounds[i][0] for i in done),
               unit="pt", unit_scale=True, desc="sweep", file=sys.stderr, disable=not progress)
    pool = multiprocessing.get_context("fork").Pool(workers) if workers > 1 else None
    try:
        for i, (a, b) in enumerate(bounds):
            if i in done:
                continue
            if stop_after_parts is not None and parts_computed >= stop_after_parts:
                return None, False
            jobs = [(evaluator, grid, s, min(s + CHUNK, b)) for s in range(a, b, CHUNK)]
            pieces = []
            for piece in (pool.imap(_run, jobs) if pool else map(_run, jobs)):
                pieces.append(piece)
                bar.update(len(piece["flags"]))
            part = {name: np.concatenate([p[name] for p in pieces]) for name in pieces[0]}
            _save_part(parts_dir / f"part_{i:05d}.npz", part)
            done[i] = part
            computed += b - a
            parts_computed += 1
    finally:
        bar.close()
        if pool:
            pool.close()
            pool.join()
    arrays = {name: np.concatenate([done[i][name] for i in range(len(bounds))])
              for name in done[0]}
    elapsed = time.perf_counter() - start_time
    landscape = Landscape(grid, key, arrays, {
        "evaluator": dataclasses.asdict(evaluator), "version": __version__,
        "points_computed": computed, "seconds": round(elapsed, 2)})
    if not landscape.feasible.any():
        shutil.rmtree(parts_dir)
        raise LandscapeError(f"no feasible point in the boundary ({grid.describe()}): every "
                             "location is out of reach, inside the body or unbalanced")
    landscape.save(output)
    shutil.rmtree(parts_dir)
    return landscape, False
