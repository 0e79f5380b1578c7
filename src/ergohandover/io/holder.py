"""One writer at a time: a run holds the folder or file it writes, and a second run on the same
one is refused in one line naming the first, before it reads or writes anything.

The hold is :class:`filelock.FileLock` on ``.<name>.lock`` beside the path: an OS ``flock``,
which the OS releases when the process dies, so a run killed mid-way never blocks the next.
``.<name>.holder`` beside it says who holds it (process, command, since when), for the message;
both are removed when the run ends.
"""

from __future__ import annotations

import contextlib
import os
import sys
import time
from collections.abc import Iterator
from pathlib import Path

from filelock import FileLock, Timeout

from ..errors import ErgohandoverError


class HeldError(ErgohandoverError, RuntimeError):
    """The path is held by another run; the message is one line."""


def _beside(path: Path, suffix: str) -> Path:
    return path.parent / f".{path.name}.{suffix}"


@contextlib.contextmanager
def hold(path: str | os.PathLike, what: str, instead: str) -> Iterator[None]:
    """Hold ``path`` for this process while the block runs.

    Args:
        path: the folder or file the run writes (it need not exist yet; its parent is created).
        what: how the message names it, as the user gave it (e.g. ``--output runs/a``).
        instead: what the user can do, e.g. ``wait for it to end, or give another --output``.

    Raises:
        HeldError: another process holds it.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    lock, holder = FileLock(_beside(path, "lock")), _beside(path, "holder")
    try:
        lock.acquire(timeout=0)
    except Timeout:
        try:
            who = holder.read_text(encoding="utf-8").strip() or "another process"
        except OSError:
            who = "another process"
        raise HeldError(f"{what} is in use by {who}: {instead}") from None
    try:
        command = " ".join([Path(sys.argv[0]).name, *sys.argv[1:]]) if sys.argv else "python"
        holder.write_text(f"process {os.getpid()} ({command}, since "
                          f"{time.strftime('%Y-%m-%d %H:%M:%S')})\n", encoding="utf-8")
        yield
    finally:
        holder.unlink(missing_ok=True)
        lock.release()
        _beside(path, "lock").unlink(missing_ok=True)
