"""PyBullet, quietly: its C library prints a build banner when it is imported and when a client
connects, which would litter a command's output (and, on stdout, corrupt a CSV). Headless
(DIRECT) clients for every computation and picture; a GUI client, PyBullet's own window, only
where a display exists (:func:`connect_gui`)."""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import sys
import time
from types import ModuleType

from .errors import ConfigError


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


DISPLAY_VARIABLES = ("DISPLAY", "WAYLAND_DISPLAY")
"""Where a window would be shown (X11, Wayland): without either, PyBullet's GUI cannot open."""
BROWSER_VIEW = "use `ergohandover view` for a browser view"


class NoDisplayError(ConfigError):
    """PyBullet's own window asked for where it cannot open; the message is one line."""


def has_display() -> bool:
    """Whether a window can open here: DISPLAY or WAYLAND_DISPLAY is set (and not empty)."""
    return any(os.environ.get(name) for name in DISPLAY_VARIABLES)


def require_display(what: str = "--gui") -> None:
    """NoDisplayError naming ``what`` (the flag or setting that asks for a window) unless
    :func:`has_display`: checked before any work, so that a command without a display stops
    at once rather than after its run."""
    if not has_display():
        raise NoDisplayError(f"{what} needs a display: neither DISPLAY nor WAYLAND_DISPLAY is "
                             f"set; {BROWSER_VIEW}")


def connect_gui(what: str = "--gui") -> int:
    """A new GUI-mode PyBullet client (its own window), connected without the banner;
    NoDisplayError naming ``what`` without a display, or when PyBullet cannot open a window
    (it opens one per process)."""
    require_display(what)
    p = pybullet()
    with silenced_output():
        client = p.connect(p.GUI)
    if client < 0:
        raise NoDisplayError(f"{what}: PyBullet could not open its window (it opens one per "
                             f"process, on a display that accepts OpenGL); {BROWSER_VIEW}")
    return client


def wait_while_open(client: int, poll_s: float = 0.1) -> None:
    """Return when the window of GUI ``client`` is closed or the user presses Ctrl-C (the
    command's work is done by then: Ctrl-C only ends the looking). ``kill`` still stops the
    program as it does elsewhere."""
    p = pybullet()
    try:
        while p.isConnected(client):
            time.sleep(poll_s)
    except KeyboardInterrupt as stop:
        # SIGTERM arrives as a KeyboardInterrupt that names its signal (executor.Stopped).
        if getattr(stop, "signal_number", signal.SIGINT) != signal.SIGINT:
            raise
