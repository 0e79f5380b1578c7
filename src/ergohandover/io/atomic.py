"""Atomic file writes: a result file is either complete or absent, never half-written."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import IO

import pandas as pd

from ..errors import ErgohandoverError


class OutputError(ErgohandoverError, OSError):
    """An output location that cannot be written; the message is one line."""


def atomic_write(path: str | os.PathLike, write: Callable[[IO], None],
                 binary: bool = False) -> Path:
    """Write a text file through ``write(handle)`` to a temporary file, then rename it.

    The temporary file sits beside the target (same file system, so the rename is atomic) and
    is removed if ``write`` fails.

    Args:
        path: the file to create or replace.
        write: fills the open handle.
        binary: open the handle in binary rather than text mode.

    Returns:
        The path written.
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise OutputError(f"output directory '{path.parent}' does not exist")
    atomic_write_all({path: write}, binary)
    return path


def atomic_write_csv(frame: pd.DataFrame, path: str | os.PathLike) -> Path:
    """Write ``frame`` (without its index) as CSV, atomically."""
    return atomic_write(path, lambda handle: frame.to_csv(handle, index=False))


def nearest_existing(path: Path) -> Path:
    """``path`` or its nearest ancestor that exists."""
    path = Path(path).absolute()
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def check_writable(path: str | os.PathLike, folder: bool = False) -> None:
    """Raise OutputError (one line, naming ``path``) unless a file (or, with ``folder``, a
    folder's files) can be written at ``path``: a file is made and removed in the nearest
    existing folder, so a read-only or virtual file system (``/proc``) is found before any
    work, and nothing is left behind."""
    path = Path(path)
    place = nearest_existing(path if folder else path.parent)
    if not place.is_dir():
        raise OutputError(f"{path}: cannot be written ('{place}' is a file)")
    try:
        fd, probe = tempfile.mkstemp(prefix=".probe.", suffix=".tmp", dir=place)
    except OSError as exc:
        raise OutputError(f"{path}: cannot be written ({exc.strerror or exc} in "
                          f"'{place}')") from None
    os.close(fd)
    Path(probe).unlink(missing_ok=True)


def atomic_write_all(writes: dict[Path, Callable[[IO], None]], binary: bool = False) -> None:
    """Several files, all or none: each is written through its ``write(handle)`` to a temporary
    file beside it (same file system, so the rename is atomic), and only when every one is
    complete are they renamed into place; a failure removes them all."""
    made: list[tuple[Path, Path]] = []
    try:
        for path, write in writes.items():
            path = Path(path)
            try:
                fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp",
                                           dir=path.parent)
            except OSError as exc:  # named as the caller gave it, not as the temporary file
                raise OutputError(f"{path}: cannot be written ({exc.strerror or exc})") from None
            made.append((Path(tmp), path))
            # mkstemp creates the file private (0600); give it the permissions open() would.
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
            with (os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", newline="")) as handle:
                write(handle)
    except BaseException:
        for tmp, _ in made:
            tmp.unlink(missing_ok=True)
        raise
    for tmp, path in made:
        os.replace(tmp, path)
