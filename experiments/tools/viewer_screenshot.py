"""The README's picture of the viewer: ``ergohandover view``'s page in headless Chromium, with
the box at the study's optimum and the 1 cm landscape of the default worker in view.

Usage: python experiments/tools/viewer_screenshot.py [--output docs/img/viewer.png]

Needs the viewer extra and Debian's ``chromium`` (software WebGL: ``--use-angle=swiftshader``).
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
from pathlib import Path

import pandas as pd

from ergohandover.landscape.store import landscape_of
from ergohandover.study.config import StudyConfig
from ergohandover.study.parts.shared import grid_of
from ergohandover.viewer.app import HandoverViewer, free_port, start_server

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--output", type=Path, default=ROOT / "docs" / "img" / "viewer.png")
    args = parser.parse_args()
    chromium = shutil.which("chromium")
    if chromium is None:
        raise SystemExit("chromium is not installed (apt-get install chromium)")
    config = StudyConfig()
    evaluator = config.evaluator()
    landscape = landscape_of(evaluator, grid_of(evaluator, config.landscape.boundary, 0.01))
    stats = pd.read_csv(ROOT / "results" / "landscape" / "stats.csv")
    best = stats[stats["score"] == "paper_postural"].iloc[0]
    optimum = best[["best_x", "best_y", "best_z"]].to_numpy(float)
    port = free_port()
    paths = sorted((ROOT / "results" / "baselines" / "paths").glob("*.csv"))
    viewer = HandoverViewer(evaluator, landscape, {"optimum": optimum}, paths,
                            start_server("127.0.0.1", port))
    try:
        viewer.ceiling.value = 6  # the cells scoring 4-6: where the good locations lie
        subprocess.run([chromium, "--headless", "--no-sandbox", "--use-gl=angle",
                        "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                        "--virtual-time-budget=90000", "--window-size=1280,800",
                        f"--screenshot={args.output}", f"http://127.0.0.1:{port}"],
                       check=True, capture_output=True, timeout=180)
    finally:
        viewer.close()
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
