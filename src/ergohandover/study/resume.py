"""A study part is resumable: it writes into its own results folder and finishes by writing a
``manifest.json`` that records the hash of what its results depend on; a part whose manifest
matches is done and is reused (so an interrupted ``run_all`` resumes where it stopped, and a
fresh clone reuses every committed part).

What decides reuse (:func:`part_hash`): the part's inputs from the typed study configuration
(:meth:`~.config.StudyConfig.part_inputs`), the package version and the source code of the twin
and the scorers (:func:`~ergohandover.landscape.twin_code_version`), so a change to the
model reruns every part.

A part never leaves a half-written folder: it writes into ``results/.partial/<part>/`` and that
folder replaces ``results/<part>/`` only when the part has finished, manifest included. A part
that fails or is stopped (Ctrl-C, ``kill``) removes its staged folder and leaves the previous
results as they were.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import shutil
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .. import __version__
from ..io.manifest import write_manifest
from ..landscape import twin_code_version


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


_ANNOUNCED: set[Path] = set()
"""The finished parts this process has said it reuses."""


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
    restore_swapped(folder)
    if not force and is_done(folder, inputs):
        if folder not in _ANNOUNCED:  # a part read by several others is said once
            print(f"[{name}] reusing finished results in {folder}")
            _ANNOUNCED.add(folder)
        return False
    stage = staging_folder(folder)
    shutil.rmtree(stage, ignore_errors=True)  # what a killed run left
    stage.mkdir(parents=True)
    try:
        start = time.perf_counter()
        extra = work(stage) or {}
        where = {"engine": {"name": engine.name, "workers": engine.workers,
                            "address": engine.address}} if engine is not None else {}
        wrote = sorted(p.name + ("/" if p.is_dir() else "") for p in stage.iterdir())
        write_manifest(stage, config={"part": name, **inputs}, seeds=seeds or {},
                       wall_time_s=time.perf_counter() - start,
                       extra={"part_hash": part_hash(inputs), "code_hash": twin_code_version(),
                              "wrote": wrote, **where, **extra})
        replace_folder(stage, folder)
    finally:
        shutil.rmtree(stage, ignore_errors=True)
        with contextlib.suppress(OSError):  # the staging area, once nothing is left in it
            stage.parent.rmdir()
    return True


STAGING = ".partial"
"""The folder beside the parts' folders where a running part writes."""


def staging_folder(folder: Path) -> Path:
    """Where the part of ``folder`` writes while it runs (same name, so that its manifest
    names the part's folder)."""
    return folder.parent / STAGING / folder.name


def replace_folder(stage: Path, folder: Path) -> None:
    """Put the finished ``stage`` in the place of ``folder``: two renames on one file system,
    the old folder set aside first and removed last (:func:`restore_swapped` puts it back if
    the process died in between)."""
    old = stage.with_name(stage.name + ".old")
    shutil.rmtree(old, ignore_errors=True)
    folder.parent.mkdir(parents=True, exist_ok=True)
    if folder.exists():
        folder.rename(old)
    stage.rename(folder)
    shutil.rmtree(old, ignore_errors=True)


def restore_swapped(folder: Path) -> None:
    """Put back a part's previous results set aside by a :func:`replace_folder` that did not
    finish (the process died between its two renames)."""
    old = staging_folder(folder).with_name(folder.name + ".old")
    if old.is_dir() and not folder.exists():
        old.rename(folder)
