"""PyBullet, quietly: its C library prints a build banner when it is imported and when a client
connects, which would litter a command's output (and, on stdout, corrupt a CSV)."""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from types import ModuleType


@contextlib.contextmanager
def silenced_output():
    """Send the process's C-level standard output and error to /dev/null for the duration."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    try:
        with open(os.devnull, "w") as sink:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            yield
            # C's stdio may buffer the banner; flush it while both still point at /dev/null.
            ctypes.CDLL(None).fflush(None)
    finally:
        for fd, copy in zip((1, 2), saved, strict=True):
            os.dup2(copy, fd)
            os.close(copy)


def pybullet() -> ModuleType:
    """The ``pybullet`` module, imported without its banner."""
    if "pybullet" not in sys.modules:
        with silenced_output():
            import pybullet as module  # noqa: F401
    return sys.modules["pybullet"]


def connect_direct() -> int:
    """A new DIRECT-mode (headless) PyBullet client, connected without the banner."""
    p = pybullet()
    with silenced_output():
        return p.connect(p.DIRECT)
