"""A study part is resumable: it writes into its own results folder and finishes by writing a
``manifest.json`` that records the hash of what its results depend on; a part whose manifest
matches is done and is reused (so an interrupted ``run_all`` resumes where it stopped, and a
fresh clone reuses every committed part).

What decides reuse (:func:`part_hash`): the part's inputs from the typed study configuration
(:meth:`~.config.StudyConfig.part_inputs`), the package version and the source code of the twin
and the scorers (:func:`~ergohandover.landscape.cache.twin_code_version`), so a change to the
model reruns every part.
"""

from __future__ import annotations

import hashlib
import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .. import __version__
from ..io.manifest import write_manifest
from ..landscape.cache import twin_code_version


def part_hash(inputs: dict[str, Any]) -> str:
    """A short hash of a part's inputs, the package version and the twin's code."""
    text = json.dumps({"config": inputs, "version": __version__, "code": twin_code_version()},
                      sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def is_done(folder: Path, inputs: dict[str, Any]) -> bool:
    """True when ``folder`` holds a finished part made with these inputs and this code."""
    try:
        manifest = json.loads((folder / "manifest.json").read_text())
    except (OSError, ValueError):
        return False
    return manifest.get("part_hash") == part_hash(inputs)


def run_part(name: str, folder: Path, inputs: dict[str, Any],
             work: Callable[[Path], dict[str, Any] | None], seeds: dict[str, int] | None = None,
             force: bool = False, engine: Any = None) -> bool:
    """Run ``work(folder)`` unless the part is already done; then write its manifest.

    Args:
        name: the part's name (for messages).
        folder: where the part writes its results.
        inputs: what the part's results depend on (hashed into the manifest, recorded whole).
        work: does the part; may return extra figures for the manifest.
        seeds: every seed used.
        force: run even if done.
        engine: where its jobs ran (recorded).

    Returns:
        True if the part ran, False if it was reused.
    """
    if not force and is_done(folder, inputs):
        print(f"[{name}] reusing finished results in {folder}")
        return False
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "manifest.json").unlink(missing_ok=True)  # not done until it is rewritten
    start = time.perf_counter()
    extra = work(folder) or {}
    where = {"engine": {"name": engine.name, "workers": engine.workers,
                        "address": engine.address}} if engine is not None else {}
    write_manifest(folder, config={"part": name, **inputs}, seeds=seeds or {},
                   wall_time_s=time.perf_counter() - start,
                   extra={"part_hash": part_hash(inputs), "code_hash": twin_code_version(),
                          **where, **extra})
    return True
