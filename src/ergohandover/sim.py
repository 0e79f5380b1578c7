"""PyBullet, quietly: its C library prints a build banner to standard output when a client
connects, which would corrupt a CSV written to standard output."""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from types import ModuleType


@contextlib.contextmanager
def silenced_stdout():
    """Send the process's C-level standard output to /dev/null for the duration."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "w") as sink:
            os.dup2(sink.fileno(), 1)
            yield
            # C's stdio buffers the banner; flush it while stdout still points at /dev/null.
            ctypes.CDLL(None).fflush(None)
    finally:
        os.dup2(saved, 1)
        os.close(saved)


def pybullet() -> ModuleType:
    """The ``pybullet`` module, imported without its banner."""
    if "pybullet" not in sys.modules:
        with silenced_stdout():
            import pybullet as module  # noqa: F401
    return sys.modules["pybullet"]


def connect_direct() -> int:
    """A new DIRECT-mode (headless) PyBullet client, connected without the banner."""
    p = pybullet()
    with silenced_stdout():
        return p.connect(p.DIRECT)
