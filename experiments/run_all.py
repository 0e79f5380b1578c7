"""Run every study of ergohandover and write results/ (with a manifest.json beside each).

Today this runs the parts that exist: it scores the example posture table
(``examples/postures.csv``) with REBA, RULA and the paper's postural score into
``results/example_scores/scores.csv``. The landscape sweep, the learners, the baselines and the
participant study join this script as they are built (see README, "What runs today").
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import pandas as pd

from ergohandover.atomic import atomic_write_csv
from ergohandover.ergonomics import ScoringSettings, score_postures
from ergohandover.manifest import write_manifest
from ergohandover.posture_csv import read_postures

ROOT = Path(__file__).resolve().parents[1]


def score_examples(results: Path) -> Path:
    start = time.perf_counter()
    settings = ScoringSettings()
    source = ROOT / "examples" / "postures.csv"
    text, posture = read_postures(source, what=str(source))
    table = pd.concat([text, pd.DataFrame(score_postures(posture, settings))], axis=1)
    folder = results / "example_scores"
    folder.mkdir(parents=True, exist_ok=True)
    out = atomic_write_csv(table, folder / "scores.csv")
    write_manifest(out, config={"input": str(source.relative_to(ROOT)), "settings": settings},
                   seeds={}, wall_time_s=time.perf_counter() - start)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", type=Path, default=ROOT / "results",
                        help="directory to write results into (default: results/)")
    args = parser.parse_args(argv)
    args.results.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    print("ergohandover run_all: scoring the example postures (the only study built so far)")
    out = score_examples(args.results)
    print(f"  wrote {out.relative_to(ROOT) if out.is_relative_to(ROOT) else out}")
    print(f"done in {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
