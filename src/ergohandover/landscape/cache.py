"""The one landscape cache: a landscape file per key, shared by the study and every command.

A landscape's key is a hash of everything that changes its content: the worker's body, the
task, the boundary and step, the solver and its settings, the scoring settings, and the source
code of the twin and the scorers (:func:`twin_code_version`), so an edit to the model can never
be answered from a stale file. Files live in :func:`cache_dir` (``$ERGOHANDOVER_CACHE``, else
``$XDG_CACHE_HOME/ergohandover``, else ``~/.cache/ergohandover``) as
``landscapes/<key>.npz``; each is written atomically and carries a checksum of its arrays, so a
file that is half-written, corrupted or made with other settings is detected, never read.

This module only names and reads files; getting a landscape (from here, or swept into here under
a lock) is :mod:`~ergohandover.landscape.store`'s job, the one door every caller uses.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import os
from pathlib import Path

import numpy as np

from .. import __version__
from ..errors import ErgohandoverError
from ..io.atomic import atomic_write
from ..twin.evaluate import Evaluator
from ..twin.task import Boundary
from .grid import Grid

PACKAGE = Path(__file__).resolve().parents[1]
MODEL_SOURCES = ("ergonomics", "twin", "frames.py", "ranges.py")
"""What computes a landscape's rows: their source files are part of every key."""


class LandscapeError(ErgohandoverError, ValueError):
    """A landscape that cannot be built or used; the message is one line."""


def cache_dir() -> Path:
    """Where landscapes are cached (created on first write); only this package looks here,
    every other module goes through :mod:`~ergohandover.landscape.store`."""
    if os.environ.get("ERGOHANDOVER_CACHE"):
        return Path(os.environ["ERGOHANDOVER_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "ergohandover"


@functools.lru_cache(maxsize=1)
def twin_code_version() -> str:
    """A hash of the source code of the twin and the scorers (:data:`MODEL_SOURCES`)."""
    digest = hashlib.sha256()
    for name in MODEL_SOURCES:
        root = PACKAGE / name
        # The code and the tables of figures it reads (the fitted body model).
        files = [p for p in root.rglob("*") if p.suffix in (".py", ".json")] \
            if root.is_dir() else [root]
        for path in sorted(files):
            digest.update(path.relative_to(PACKAGE).as_posix().encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def landscape_key(evaluator: Evaluator, grid: Grid) -> str:
    """A hash of everything that determines a landscape's content."""
    spec = {"evaluator": dataclasses.asdict(evaluator), "grid": dataclasses.asdict(grid),
            "version": __version__, "code": twin_code_version()}
    return hashlib.sha256(json.dumps(spec, sort_keys=True).encode()).hexdigest()[:16]


def landscape_path(key: str) -> Path:
    """The cache file of the landscape with ``key`` (callers outside this package read a
    landscape's own ``path``)."""
    return cache_dir() / "landscapes" / f"{key}.npz"


def checksum(arrays: dict[str, np.ndarray]) -> str:
    """SHA-256 over the arrays' names and bytes, in name order."""
    digest = hashlib.sha256()
    for name in sorted(arrays):
        digest.update(name.encode())
        digest.update(np.ascontiguousarray(arrays[name]).tobytes())
    return digest.hexdigest()


@dataclasses.dataclass
class Landscape:
    """Compact per-point results in grid order (flat, C order: x slowest).

    ``arrays``: ``flags`` (uint8 bit mask of :data:`~ergohandover.twin.evaluate.REASONS`,
    0 = feasible), each score of :data:`~ergohandover.landscape.sweep.SCORES` as int8 (-1 where
    infeasible) and each of :data:`~ergohandover.landscape.sweep.ANGLES` as float32 [deg, m].
    ``path`` is the file it was loaded from or last saved to (None for one made in memory), so
    that a caller can name the cache file without computing where it is.
    """

    grid: Grid
    key: str
    arrays: dict[str, np.ndarray]
    meta: dict
    path: Path | None = dataclasses.field(default=None, compare=False)

    @property
    def feasible(self) -> np.ndarray:
        return self.arrays["flags"] == 0

    def save(self, path: Path) -> Path:
        """Write the landscape (atomically) with its key, grid and checksum; sets ``path``."""
        path = Path(path)
        meta = {**self.meta, "key": self.key, "checksum": checksum(self.arrays),
                "grid": dataclasses.asdict(self.grid)}
        path.parent.mkdir(parents=True, exist_ok=True)
        # Uncompressed: zlib took 7 s of a 2-minute sweep for a third off the size of a file
        # that is a cache, never committed.
        self.path = atomic_write(path, lambda h: np.savez(
            h, meta=np.array(json.dumps(meta)), **self.arrays), binary=True)
        return self.path

    @classmethod
    def load(cls, path: Path, key: str | None = None) -> Landscape:
        """Read and verify a landscape file (any file: a user's, or the cache's through
        :mod:`~ergohandover.landscape.store`); LandscapeError if unreadable, corrupted or
        mismatched."""
        path = Path(path)
        try:
            with np.load(path) as data:
                meta = json.loads(str(data["meta"]))
                arrays = {name: data[name] for name in data.files if name != "meta"}
        except FileNotFoundError:
            raise LandscapeError(f"landscape = '{path}' does not exist") from None
        except Exception as exc:  # any unreadable file is a corrupted one
            raise LandscapeError(f"{path} is not a readable landscape ({type(exc).__name__})") \
                from None
        if key is not None and meta.get("key") != key:
            raise LandscapeError(f"{path} was made with other settings (key {meta.get('key')}, "
                                 f"expected {key})")
        if meta.get("checksum") != checksum(arrays):
            raise LandscapeError(f"{path} is corrupted (checksum mismatch)")
        g = meta["grid"]
        grid = Grid(Boundary(tuple(g["boundary"]["x"]), tuple(g["boundary"]["y"]),
                             tuple(g["boundary"]["z"]), g["boundary"]["name"]), g["step"])
        return cls(grid, meta["key"], arrays, meta, path)
