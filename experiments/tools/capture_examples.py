"""Write the example keypoint files in examples/keypoints/: the worker twin (ANSUR II
50th-percentile man, the study's box) taking the box at six handover locations, placed as each
format places its joints and written as that format's tools write it, in its own frame.

Usage: python experiments/tools/capture_examples.py [--output examples/keypoints]

One file per format, each in another container (so that every reader has an example):
h36m17.csv (wide CSV, y down, as VideoPose3D's camera frame), coco17_long.csv (long CSV, y
down), mediapipe33.json (MediaPipe Pose world landmarks, y down, origin at the hips),
zed34.npz (z up, as the ZED SDK's world frame), smpl24.npy (y up) and twin.bvh (CMU joint names,
y up, centimetres). The people stand 2.5 m in front of the camera (camera frames) or where the
twin stands (world frames). ``ergohandover score --keypoints FILE --format NAME`` scores them;
tests/test_cli_capture.py checks that each scores as the twin's own postures do.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pandas as pd

from ergohandover.capture import FORMATS
from ergohandover.capture.placement import place
from ergohandover.capture.twin_bvh import twin_bvh
from ergohandover.twin.evaluate import Evaluator, evaluate, joint_angles
from ergohandover.twin.kinematics import KinematicModel
from ergohandover.twin.skeleton import build_skeleton

ROOT = Path(__file__).resolve().parents[2]
LOCATIONS = np.array([[0.0, 1.00, 0.41], [0.0, 0.80, 0.50], [0.15, 1.30, 0.55],
                      [-0.15, 0.90, 0.35], [0.0, 1.40, 0.45], [0.10, 0.85, 0.45]])
"""Box centres in the worker frame [m] (x right, y up, z forward)."""
CAMERA_DEPTH_M = 2.5
"""How far in front of a camera the person stands (camera frames: z into the scene)."""


def postures(evaluator: Evaluator):
    """The twin's solved postures at :data:`LOCATIONS` (every one feasible)."""
    table = evaluate(LOCATIONS, evaluator, joints=True)
    if not table["feasible"].all():
        raise SystemExit(f"infeasible example locations: {table[table['feasible'] == 0]}")
    return KinematicModel(build_skeleton(evaluator.body)).forward(joint_angles(table))


def in_camera(points: np.ndarray) -> np.ndarray:
    """Points written with y down (a camera facing the person, CAMERA_DEPTH_M away)."""
    return points + np.array([0.0, 0.0, CAMERA_DEPTH_M])


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--output", type=Path, default=ROOT / "examples" / "keypoints")
    args = parser.parse_args()
    evaluator = Evaluator()
    state = postures(evaluator)
    body, out = evaluator.body, args.output
    out.mkdir(parents=True, exist_ok=True)
    frames = np.arange(1, len(LOCATIONS) + 1)

    h36m = FORMATS["h36m17"]
    points = in_camera(place(state, body, h36m)).round(5)
    wide = pd.DataFrame(points.reshape(len(frames), -1),
                        columns=[f"{j}_{a}" for j in h36m.joints for a in "xyz"])
    wide.insert(0, "frame", frames)
    wide.to_csv(out / "h36m17.csv", index=False)

    coco = FORMATS["coco17"]
    points = in_camera(place(state, body, coco)).round(5)
    long = pd.DataFrame([{"frame": f, "joint": j, "x": p[0], "y": p[1], "z": p[2]}
                         for f, frame in zip(frames, points, strict=True)
                         for j, p in zip(coco.joints, frame, strict=True)])
    long.to_csv(out / "coco17_long.csv", index=False)

    mediapipe = FORMATS["mediapipe33"]
    points = place(state, body, mediapipe)
    hips = points[:, [mediapipe.index("left_hip"), mediapipe.index("right_hip")]].mean(axis=1)
    points = (points - hips[:, None]).round(5)  # world landmarks: origin at the hips' centre
    doc = [{"pose_world_landmarks": [{"x": p[0], "y": p[1], "z": p[2], "visibility": 0.99}
                                     for p in frame.tolist()]} for frame in points]
    (out / "mediapipe33.json").write_text(json.dumps(doc, indent=1) + "\n")

    np.savez(out / "zed34.npz", keypoints=place(state, body, FORMATS["zed34"]).round(5))
    np.save(out / "smpl24.npy", place(state, body, FORMATS["smpl24"]).round(5))
    (out / "twin.bvh").write_text(twin_bvh(state, body, up="y", units="cm", decimals=4))
    print(f"wrote {len(frames)} frames per format into {out}")


if __name__ == "__main__":
    main()
