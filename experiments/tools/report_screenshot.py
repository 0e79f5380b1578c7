"""The docs' picture of a report page: ``ergohandover report`` at the study's recommended
location (the landscape's optimum) for the default worker, its first page in headless Chromium.

Usage: python experiments/tools/report_screenshot.py [--output docs/img/report.png]

Needs Debian's ``chromium`` and the committed results (the optimum and the workforce's share).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import pandas as pd

from ergohandover.viewer.chromium import screenshot

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--output", type=Path, default=ROOT / "docs" / "img" / "report.png")
    args = parser.parse_args()
    stats = pd.read_csv(ROOT / "results" / "landscape" / "stats.csv")
    best = stats[stats["score"] == "paper_postural"].iloc[0]
    where = ",".join(f"{best[f'best_{a}']:g}" for a in "xyz")
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([sys.executable, "-m", "ergohandover.cli", "report", "--location", where,
                        "--results", str(ROOT / "results"), "--output", folder], check=True)
        screenshot(Path(folder) / "report.html", args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
