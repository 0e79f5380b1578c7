"""Render the default worker at five representative box locations for docs/report.md.

Usage: python experiments/render_examples.py [--out docs/img]

Writes ``twin_<name>.png`` (three-quarter and side views, scores underneath) and
``twin_examples.csv`` (their Evaluation rows) into ``--out``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from ergohandover.io.atomic import atomic_write_csv
from ergohandover.scene.render import render_points
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import EVALUATION_COLUMNS, Evaluator, evaluate
from ergohandover.twin.task import TaskSpec

ROOT = Path(__file__).resolve().parents[1]


def examples(body: BodySpec) -> dict[str, tuple[float, float, float]]:
    """Box centres (worker frame, m): low, waist, chest, overhead, and out to the right."""
    seg = body.segments()
    return {
        "low": (0.0, seg.knee_height, 0.40),
        "waist": (0.0, seg.hip_height + 0.05, 0.40),
        "chest": (0.0, seg.shoulder_height - 0.15, 0.40),
        "overhead": (0.0, body.stature_m + 0.10, 0.35),
        "side": (0.35, seg.hip_height + 0.15, 0.45),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "img")
    args = parser.parse_args()
    body, task = BodySpec(), TaskSpec()
    named = examples(body)
    points = np.array(list(named.values()))
    evaluator = Evaluator(body, task)
    table = evaluate(points, evaluator, joints=True)
    table.insert(0, "name", list(named))
    args.out.mkdir(parents=True, exist_ok=True)
    atomic_write_csv(table[["name", *EVALUATION_COLUMNS]], args.out / "twin_examples.csv")
    render_points(table, points, evaluator, args.out)
    for i, name in enumerate(named, start=1):
        (args.out / f"point_{i:04d}.png").replace(args.out / f"twin_{name}.png")
    print(table[["name", "x", "y", "z", "feasible", "trunk_flexion", "left_knee_flexion",
                 "neck_flexion", "left_elbow_flexion", "reba", "rula",
                 "paper_postural"]].round(2).to_string(index=False))


if __name__ == "__main__":
    main()
