"""Headless Chromium (Debian's ``chromium``): print a page to PDF or take its screenshot."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from ..errors import ErgohandoverError

FLAGS = ("--headless", "--no-sandbox", "--use-gl=angle", "--use-angle=swiftshader",
         "--enable-unsafe-swiftshader", "--no-pdf-header-footer")
"""Software WebGL, no sandbox (a container), no date or URL printed on the page."""


class ChromiumError(ErgohandoverError, RuntimeError):
    """Chromium is missing or failed; the message is one line."""


def chromium() -> str:
    """The path of the ``chromium`` executable; ChromiumError if it is not installed."""
    found = shutil.which("chromium") or shutil.which("chromium-browser")
    if found is None:
        raise ChromiumError("chromium is not installed (Debian: apt-get install chromium); it "
                            "prints the report to PDF")
    return found


def _run(page: Path, output_flag: str, extra: tuple[str, ...] = ()) -> None:
    command = [chromium(), *FLAGS, *extra, output_flag, Path(page).resolve().as_uri()]
    try:
        subprocess.run(command, check=True, capture_output=True, timeout=180)
    except (subprocess.CalledProcessError, subprocess.TimeoutExpired) as exc:
        raise ChromiumError(f"chromium could not render {page} "
                            f"({type(exc).__name__})") from None


def print_pdf(page: Path, pdf: Path) -> Path:
    """``page`` (a local HTML file) printed to ``pdf``."""
    _run(page, f"--print-to-pdf={pdf}")
    return pdf


def screenshot(page: Path, png: Path, size: tuple[int, int] = (900, 1270)) -> Path:
    """A PNG of ``page`` (a local HTML file) in a window of ``size`` pixels."""
    _run(page, f"--screenshot={png}", (f"--window-size={size[0]},{size[1]}",
                                       "--virtual-time-budget=5000", "--hide-scrollbars"))
    return png


class DevToolsPage:
    """One page of headless Chromium (software WebGL) driven through its DevTools protocol, so
    that a caller waits in real time for what a person would wait for (a page's panel, a
    scene's fade-in): a fixed virtual-time budget can end before a busy machine has drawn it.
    Needs ``websockets`` (the viewer extra's)."""

    def __init__(self, size: tuple[int, int] = (1280, 800), start_s: float = 60.0):
        import json
        import socket
        import time
        import urllib.request

        from websockets.sync.client import connect

        with socket.socket() as probe:  # a free port for the protocol
            probe.bind(("127.0.0.1", 0))
            port = probe.getsockname()[1]
        self.process = subprocess.Popen(
            [chromium(), *FLAGS[:-1], f"--remote-debugging-port={port}",
             "--remote-allow-origins=*", f"--window-size={size[0]},{size[1]}", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        pages, deadline = [], time.monotonic() + start_s
        while not pages:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list") as answer:
                    pages = [t for t in json.load(answer) if t["type"] == "page"]
            except OSError:
                pass
            if not pages and time.monotonic() > deadline:
                self.process.kill()
                raise ChromiumError("headless Chromium did not start")
            time.sleep(0.2)
        self.socket = connect(pages[0]["webSocketDebuggerUrl"], max_size=None)
        self.calls = 0
        self.call("Emulation.setDeviceMetricsOverride", width=size[0], height=size[1],
                  deviceScaleFactor=1, mobile=False)

    def call(self, method: str, **params) -> dict:
        """One protocol command and its result."""
        import json

        self.calls += 1
        self.socket.send(json.dumps({"id": self.calls, "method": method, "params": params}))
        while True:
            message = json.loads(self.socket.recv())
            if message.get("id") == self.calls:
                return message.get("result", {})

    def evaluate(self, expression: str):
        """The value of a JavaScript expression in the page."""
        found = self.call("Runtime.evaluate", expression=expression, returnByValue=True)
        return found.get("result", {}).get("value")

    def html(self) -> str:
        return self.evaluate("document.body.innerHTML") or ""

    def navigate(self, url: str) -> None:
        self.call("Page.navigate", url=url)

    def png(self) -> bytes:
        """A screenshot of the page."""
        import base64

        return base64.b64decode(self.call("Page.captureScreenshot", format="png")["data"])

    def close(self) -> None:
        self.socket.close()
        self.process.kill()
        self.process.wait()
