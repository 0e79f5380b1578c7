"""The README's picture of the viewer: what ``ergohandover view`` opens on a fresh clone (an
empty landscape cache), in headless Chromium.

The command itself serves the page, with its own defaults (the landscape it shows, the box at
the optimum, the cloud's filter, the camera), so the picture is what a user sees; Chromium's
notice that WebGL runs in software (true here, not on a user's machine) is hidden before the
screenshot.

Usage: python experiments/tools/viewer_screenshot.py [--output docs/img/viewer.png]
       [--use-cache]

Needs the viewer extra and Debian's ``chromium`` (software WebGL: ``--use-angle=swiftshader``).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ergohandover.viewer.app import free_port
from ergohandover.viewer.chromium import DevToolsPage, chromium

ROOT = Path(__file__).resolve().parents[2]
SIZE = (1280, 800)
READY = "robot: holds the box here"  # the panel of the box at the optimum
HIDE_NOTICES = ("document.querySelectorAll('.mantine-Notifications-root')"
                ".forEach(n => n.style.display = 'none')")


class DevTools(DevToolsPage):
    """The page shot once it has drawn the scene."""

    def shoot(self, url: str, timeout_s: float = 180.0) -> bytes:
        """The page at ``url`` once its panel shows :data:`READY` and two screenshots a few
        seconds apart agree (the scene's meshes have faded in)."""
        self.navigate(url)
        deadline = time.monotonic() + timeout_s
        while READY not in (self.evaluate("document.body.innerHTML") or ""):
            if time.monotonic() > deadline:
                raise SystemExit(f"the viewer's page did not show {READY!r}")
            time.sleep(0.5)
        self.evaluate(HIDE_NOTICES)
        last, shot = b"", self.png()
        while shot != last and time.monotonic() < deadline:
            time.sleep(3.0)
            self.evaluate(HIDE_NOTICES)
            last, shot = shot, self.png()
        return shot

def serve(port: int, cache: Path | None) -> subprocess.Popen:
    """``ergohandover view`` on ``port`` (the landscape cache ``cache``, else the user's), once
    it says where it serves."""
    env = dict(os.environ)
    if cache is not None:
        env["ERGOHANDOVER_CACHE"] = str(cache)
    script = Path(sys.executable).with_name("ergohandover")  # the command as a user types it
    ergohandover = [str(script)] if script.is_file() else [sys.executable, "-m",
                                                            "ergohandover.cli"]
    began = time.monotonic()
    command = subprocess.Popen([*ergohandover, "view", "--port", str(port), "--seconds", "900"],
                               stdout=subprocess.PIPE, text=True, env=env)
    for line in command.stdout:
        if line.startswith("viewer at"):
            print(f"{line.strip()} after {time.monotonic() - began:.1f} s", file=sys.stderr)
            return command
    raise SystemExit(f"ergohandover view stopped (exit code {command.wait()})")


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--output", type=Path, default=ROOT / "docs" / "img" / "viewer.png")
    parser.add_argument("--use-cache", action="store_true",
                        help="the landscape cache as it is (default: an empty one, as on a "
                        "fresh clone)")
    args = parser.parse_args()
    chromium()  # installed, or one line saying how
    port = free_port()
    with tempfile.TemporaryDirectory() as empty:
        command = serve(port, None if args.use_cache else Path(empty))
        browser = DevTools(SIZE)
        try:
            args.output.write_bytes(browser.shoot(f"http://127.0.0.1:{port}"))
        finally:
            browser.close()
            command.terminate()
            command.wait()
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
