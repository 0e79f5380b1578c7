"""``manifest.json`` beside every result: what produced it, so that a reviewer can redo it."""

from __future__ import annotations

import dataclasses
import json
import os
import platform
import subprocess
import sys
from importlib import metadata
from pathlib import Path
from typing import Any

from ..errors import SerialisationError
from .atomic import atomic_write

PACKAGES = ("ergohandover", "numpy", "pandas", "pybullet", "gymnasium", "stable-baselines3",
            "torch", "seaborn", "tqdm")


# Output folders: a study run rewrites them, which does not make the code differ from the commit.
OUTPUTS = ("results", "paper_figs")


def git_state(cwd: str | os.PathLike | None = None) -> dict[str, Any]:
    """The checkout's commit, whether tracked files other than the outputs (:data:`OUTPUTS`)
    differ from it, and which (``dirty_files``, at most 50); ``commit`` None outside a git
    checkout. A result made from a tree that differs from its commit says so and how."""
    try:
        run = lambda *a: subprocess.run(  # noqa: E731
            ["git", *a], cwd=cwd, capture_output=True, text=True, timeout=10, check=True
        ).stdout.rstrip()  # a status line starts with a space: keep it
        commit = run("rev-parse", "HEAD")
        changed = run("status", "--porcelain", "--untracked-files=no", "--", ":(top)",
                      *(f":(top,exclude){folder}" for folder in OUTPUTS))
    except (OSError, subprocess.SubprocessError):
        return {"commit": None, "dirty": None, "dirty_files": []}
    files = [line[3:] for line in changed.splitlines()]
    return {"commit": commit, "dirty": bool(files), "dirty_files": files[:50]}


def package_versions() -> dict[str, str | None]:
    versions = {}
    for name in PACKAGES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = None
    return versions


def _jsonable(value: Any) -> Any:
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return dataclasses.asdict(value)
    if isinstance(value, Path):
        return str(value)
    raise SerialisationError(f"not JSON-serialisable: {type(value).__name__}")


def write_manifest(result: str | os.PathLike, config: dict[str, Any], seeds: dict[str, int],
                   wall_time_s: float, extra: dict[str, Any] | None = None) -> Path:
    """Write ``manifest.json`` in the directory of ``result`` (atomically).

    Args:
        result: the result file (or directory) the manifest describes.
        config: the resolved configuration (dataclasses are expanded).
        seeds: every seed used, by concern.
        wall_time_s: wall time of the run [s].
        extra: anything else worth keeping (e.g. figures measured).
    """
    result = Path(result)
    folder = result if result.is_dir() else result.parent
    here = Path(__file__).resolve().parent
    manifest = {
        "result": result.name,
        "command": " ".join([Path(sys.argv[0]).name, *sys.argv[1:]]),
        "config": config,
        "seeds": seeds,
        "git": git_state(here),
        "versions": {"python": platform.python_version(), **package_versions()},
        "machine": {"platform": platform.platform(), "processor": platform.machine(),
                    "cpus": os.cpu_count()},
        "wall_time_s": round(wall_time_s, 3),
        **(extra or {}),
    }
    text = json.dumps(manifest, indent=2, default=_jsonable) + "\n"
    return atomic_write(folder / "manifest.json", lambda handle: handle.write(text))
