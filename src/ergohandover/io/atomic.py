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
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        # mkstemp creates the file private (0600); give it the permissions open() would.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        with (os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", newline="")) as handle:
            write(handle)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def atomic_write_csv(frame: pd.DataFrame, path: str | os.PathLike) -> Path:
    """Write ``frame`` (without its index) as CSV, atomically."""
    return atomic_write(path, lambda handle: frame.to_csv(handle, index=False))
