"""Benchmark: the peak memory of ``ergohandover score --keypoints`` on a long file, and its time
as a ratio to a short one scored in the same run.

Usage: python experiments/bench_capture_memory.py [--frames N] [--reference N] [--format F]

Writes a wide keypoint CSV of ``--frames`` frames (default 2,000,000; the worker twin's
postures over 60 % of its joint ranges, each written with 6 decimals, in a temporary folder
removed at the end), scores it with ``ergohandover score --keypoints FILE --yes`` in a
subprocess and reads that subprocess's peak resident memory (``getrusage`` of the children).
The same is done first for a file of ``--reference`` frames (default 100,000), and the long
file's frames per second are given as a ratio to the short one's: the machine may be shared
and noisy, which the ratio is less sensitive to. The target is a peak under 1 GB.
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ergohandover.capture import keypoint_format
from ergohandover.capture.placement import place
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.kinematics import KinematicModel
from ergohandover.twin.skeleton import build_skeleton

TARGET_BYTES = 1e9
POSTURES = 20_000
"""Distinct postures drawn; the file repeats them (parsing and scoring cost the same)."""


def write_file(path: Path, frames: int, fmt_name: str) -> None:
    """A wide CSV of ``frames`` frames, written a block at a time."""
    body = BodySpec()
    model = KinematicModel(build_skeleton(body))
    rng = np.random.default_rng(0)
    q = rng.uniform(0.6 * model.lower, 0.6 * model.upper, (POSTURES, model.nq))
    fmt = keypoint_format(fmt_name)
    points = place(model.forward(q), body, fmt).reshape(POSTURES, -1)
    header = ",".join(["frame", *(f"{j}_{a}" for j in fmt.joints for a in "xyz")])
    with open(path, "w") as handle:
        handle.write(header + "\n")
        for start in range(0, frames, POSTURES):
            count = min(POSTURES, frames - start)
            block = np.column_stack([np.arange(start + 1, start + count + 1), points[:count]])
            np.savetxt(handle, block, fmt=["%d"] + ["%.6f"] * points.shape[1], delimiter=",")


def score(path: Path, fmt_name: str) -> tuple[float, float]:
    """(seconds, peak resident bytes) of scoring ``path`` in a child process: the child's own
    peak, as each run's child is the largest so far (the short one runs first)."""
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "ergohandover.cli", "score", "--keypoints", str(path),
                    "--format", fmt_name, "--output", str(path.with_suffix(".scores.csv")),
                    "--yes"], check=True, stderr=subprocess.DEVNULL)
    seconds = time.perf_counter() - start
    return seconds, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024.0


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--frames", type=int, default=2_000_000, help="frames of the long file")
    parser.add_argument("--reference", type=int, default=100_000,
                        help="frames of the short file the time is compared with")
    parser.add_argument("--format", default="h36m17", help="keypoint format (default: h36m17)")
    args = parser.parse_args()

    print(f"machine: {os.cpu_count()} cores, {platform.processor() or platform.machine()}, "
          f"Python {platform.python_version()}, numpy {np.__version__}")
    with tempfile.TemporaryDirectory() as folder:
        rows = {}
        for frames in (args.reference, args.frames):
            path = Path(folder) / f"keypoints_{frames}.csv"
            write_file(path, frames, args.format)
            seconds, peak = score(path, args.format)
            rows[frames] = frames / seconds
            print(f"{frames:>10,} frames ({path.stat().st_size / 1e6:,.0f} MB of CSV): peak "
                  f"{peak / 1e6:,.0f} MB, {seconds:,.1f} s")
            path.unlink()
            path.with_suffix(".scores.csv").unlink()
    ratio = rows[args.frames] / rows[args.reference]
    print(f"{args.frames:,} frames: {ratio:.2f} x the frames/s of {args.reference:,}; peak "
          f"{peak / 1e6:,.0f} MB (target under {TARGET_BYTES / 1e6:,.0f} MB: "
          f"{'meets' if peak < TARGET_BYTES else 'MISSES'})")


if __name__ == "__main__":
    main()
