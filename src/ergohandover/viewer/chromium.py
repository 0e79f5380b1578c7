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
