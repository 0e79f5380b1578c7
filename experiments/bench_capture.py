"""Benchmark: frames per second from 3D keypoints to scores, per format, on one core, and the
ratio to scoring the same postures given as ready-made angles, measured in the same run.

Usage: python experiments/bench_capture.py [--frames N] [--repeats K] [--seed S]

The frames are the worker twin's postures over 60 % of its joint ranges (drawn once, placed as
each format places its joints; not timed). Each repeat runs the capture layer whole on them:
keypoints -> Posture columns (:func:`ergohandover.capture.capture`) -> REBA, RULA and the
paper's score, exact or as intervals over what the format cannot see
(:func:`ergohandover.capture.capture_scores`). The reference is
:func:`ergohandover.ergonomics.score_postures` on the twin's own columns (every score column).
The median repeat is printed; the target is 100,000 frames/s for H36M-17 with scoring. A figure,
not a test: the machine may be shared and noisy, which the ratio is less sensitive to.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import numpy as np

from ergohandover.capture import FORMATS, capture, capture_scores
from ergohandover.capture.placement import place
from ergohandover.ergonomics import Posture, score_postures
from ergohandover.twin.angles import posture_columns
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.kinematics import KinematicModel
from ergohandover.twin.skeleton import build_skeleton
from ergohandover.twin.task import TaskSpec

TARGET_PER_S = 100_000


def median_time(run, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--frames", type=int, default=200_000, help="frames per repeat")
    parser.add_argument("--repeats", type=int, default=5, help="timed repeats")
    parser.add_argument("--seed", type=int, default=0, help="seed of the postures")
    args = parser.parse_args()

    body = BodySpec()
    model = KinematicModel(build_skeleton(body))
    rng = np.random.default_rng(args.seed)
    q = rng.uniform(0.6 * model.lower, 0.6 * model.upper, (args.frames, model.nq))
    state = model.forward(q)
    posture = Posture(posture_columns(state, TaskSpec()))
    score_postures(posture.take(np.arange(1000)))  # warm-up
    reference = args.frames / median_time(lambda: score_postures(posture), args.repeats)
    print(f"machine: {platform.processor() or platform.machine()}, numpy {np.__version__}")
    print(f"{args.frames:,} frames x {args.repeats} repeats, median; one core")
    print(f"ready-made angles (score_postures, every column): {reference:,.0f} postures/s")
    for name, fmt in FORMATS.items():
        points = place(state, body, fmt)
        capture_scores(capture(points[:1000], fmt))  # warm-up (the band edges are cached)
        rate = args.frames / median_time(lambda: capture_scores(capture(points, fmt)),  # noqa: B023
                                         args.repeats)
        open_share = capture(points, fmt).unseen.any(axis=1).mean()
        verdict = ""
        if name == "h36m17":
            verdict = f" (target {TARGET_PER_S:,}: {'meets' if rate >= TARGET_PER_S else 'MISSES'})"
        print(f"{name:12s} keypoints -> scores: {rate:,.0f} frames/s, {rate / reference:.2f} x "
              f"ready-made angles; {100 * open_share:.0f} % of frames with an unseen column"
              f"{verdict}")


if __name__ == "__main__":
    main()
