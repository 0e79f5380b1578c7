"""Where and how people received an object in Kim et al.'s 1,000 recorded human-human handovers:
the transfer moment, the object's location relative to the receiver's body, the receiver's body
sizes and posture there, and its REBA, RULA and paper score (intervals where ZED BODY_34 cannot
see a column). Derived figures only: the data stay outside the project.

Usage: python experiments/tools/derive_measured_handovers.py DATA_DIR [--output FILE]

Data: the "Dynamic Human-to-Human Handover Dataset" of H. Kim et al., "Learning-based Dynamic
Robot-to-Human Handover", ICRA 2025, arXiv:2502.12602, public at
https://github.com/hyeonseong-kim98/dynamic_handover_dataset (no licence file: take a copy
yourself and pass its folder; nothing of it is part of this project). DATA_DIR is searched
recursively for ``*.pkl``; each is one handover, a pickled dict of ``pose_receiver`` and
``pose_giver`` (T, 34, 3: ZED BODY_34 keypoints of a ZED2i camera), ``pose_object`` (T, 3: the
object's OptiTrack marker) and ``quat_object`` (T, 4), metres, z up, 30 Hz. Pickles run code
when loaded: point this only at a copy you trust.

Definitions (one handover):

- Transfer frame: ``ergohandover.study.people.transfer`` (the object moves with the receiver's
  hand and no longer with the giver's, from the ZED hand points BODY_34 joints 8 and 15); a handover
  without one is dropped with the reason.
- Receiver frame at the transfer: origin on the floor below the middle of the ankles; forward
  horizontal, normal to the hips' left-right line, toward the receiver's front (the capture
  layer's heading frame); height above the floor (z = 0 of the recording).
- Object: its marker's forward and lateral offsets and height; also its height above the
  receiving elbow and shoulder and relative to the pelvis.
- Receiving hand: its BODY_34 hand point in the same frame (``hand_*``), where the twin's grip
  is put to predict the posture (the object's marker is not where the hand holds it).
- Sizes: median over the recording of the receiver's segment lengths (the tracker's fixed-ratio
  skeleton: they say more of the tracker than of the person), and the head-point-to-heel and
  shoulder-to-heel heights in frames where the knees are straight (standing).
- Posture: the receiver's keypoints at the transfer frame through ``ergohandover.capture``
  (format zed34, up z); unseen columns are null; scores with no load known (the object's mass is
  not in the data set) as intervals.
- Neutral and spread of each compared angle (``ergohandover.study.people.beside_people.
  COMPARED``): ``neutral_*``, its median over the recording's standing frames (the same frames
  as the heights: a calibration of the angle's zero, where the recording stands); ``spread_*``,
  its standard deviation over the frames within ``SPREAD_FRAMES`` of the transfer (what one
  frame's reading varies by around the moment: tracker jitter and motion together).

Output: CSV, one row per handover file in name order (metres to 1 mm, degrees to 0.1 deg; a
first line ``# source: ...``), written through a temporary file and os.replace: each handover's
figures, or for one without a transfer only ``dropped``, the reason.
"""

from __future__ import annotations

import argparse
import os
import pickle
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

from ergohandover.capture import capture, capture_scores, keypoint_format
from ergohandover.ergonomics.posture import COLUMN_BY_NAME, POSTURE_COLUMNS
from ergohandover.study.people.beside_people import COMPARED
from ergohandover.study.people.transfer import TransferError, transfer

ROOT = Path(__file__).resolve().parents[2]
OUTPUT = ROOT / "src" / "ergohandover" / "study" / "people" / "measured_handovers.csv"
FPS = 30.0
HANDS = (8, 15)
"""BODY_34's left and right hand points."""
SOURCE = ("Kim et al., Learning-based Dynamic Robot-to-Human Handover, ICRA 2025, "
          "arXiv:2502.12602; data github.com/hyeonseong-kim98/dynamic_handover_dataset")
STANDING_KNEE_DEG = 10.0
"""Frames whose knees are both flexed less than this count as standing, for the height."""
SPREAD_FRAMES = 3
"""Frames either side of the transfer over which each angle's spread is taken (0.1 s)."""
SEGMENTS = {"thigh": ("hip", "knee"), "shank": ("knee", "ankle"),
            "upper_arm": ("shoulder", "elbow"), "forearm": ("elbow", "wrist")}


def handover(path: Path) -> dict:
    """One handover's figures (the module's definitions); TransferError if it has no transfer."""
    with path.open("rb") as handle:
        data = pickle.load(handle)  # the user's own copy of the data set (the docstring)
    receiver = np.asarray(data["pose_receiver"], dtype=np.float64)
    giver = np.asarray(data["pose_giver"], dtype=np.float64)
    obj = np.asarray(data["pose_object"], dtype=np.float64)
    found = transfer(obj, receiver[:, HANDS], giver[:, HANDS], FPS)
    fmt = keypoint_format("zed34")
    frame = found.frame
    side = ("left", "right")[found.hand]
    # In the receiver's heading frame at the transfer, from the mid-hip: forward, left, up.
    points = receiver[frame]
    hips = (points[fmt.index("left_hip")] + points[fmt.index("right_hip")]) / 2
    heading = _heading(points, fmt)
    at = heading.T @ (obj[frame] - hips)
    ankles = heading.T @ ((points[fmt.index("left_ankle")] + points[fmt.index("right_ankle")])
                          / 2 - hips)
    location = {
        "forward_m": at[0] - ankles[0], "lateral_m": at[1] - ankles[1], "height_m": obj[frame, 2],
        "forward_of_pelvis_m": at[0], "lateral_of_pelvis_m": at[1],
        "above_pelvis_m": at[2], "above_elbow_m": obj[frame, 2] - receiver[
            frame, fmt.index(f"{side}_elbow"), 2],
        "above_shoulder_m": obj[frame, 2] - receiver[frame, fmt.index(f"{side}_shoulder"), 2],
        "pelvis_height_m": hips[2]}
    hand = heading.T @ (points[HANDS[found.hand]] - hips) - ankles
    location.update(hand_forward_m=hand[0], hand_lateral_m=hand[1],
                    hand_height_m=points[HANDS[found.hand], 2])
    captured = capture(receiver[frame:frame + 1], fmt, "z")
    scores = capture_scores(captured)
    posture = {name: (None if captured.unseen[0, i] else round(float(
        captured.columns[name][0]), 1)) for i, name in enumerate(POSTURE_COLUMNS)
        if COLUMN_BY_NAME[name].kind == "angle"}
    sizes, standing = _sizes(receiver, fmt)
    return {"handover": path.stem, "frames": len(obj), "transfer_frame": frame,
            "receiving_hand": side, "hand_to_object_m": round(found.distance, 3),
            **{k: round(float(v), 3) for k, v in location.items()},
            **sizes, **posture,
            **{name: int(values[0]) for name, values in scores.items()
               if name.endswith(("_lo", "_hi"))},
            **_neutral_and_spread(capture(receiver, fmt, "z"), standing, frame)}


def _neutral_and_spread(captured, standing: np.ndarray, frame: int) -> dict[str, float | None]:
    """Each compared angle's median over the standing frames and its standard deviation over
    the frames within SPREAD_FRAMES of the transfer [deg] (None where no frame shows it)."""
    out = {}
    near = np.zeros(len(standing), dtype=bool)
    near[max(frame - SPREAD_FRAMES, 0):frame + SPREAD_FRAMES + 1] = True
    for name in COMPARED:
        seen = ~captured.unseen[:, POSTURE_COLUMNS.index(name)]
        values = captured.columns[name]
        calm, around = values[seen & standing], values[seen & near]
        out[f"neutral_{name}"] = round(float(np.median(calm)), 1) if calm.size else None
        out[f"spread_{name}"] = round(float(np.std(around)), 2) if around.size > 1 else None
    return out


def _heading(points: np.ndarray, fmt) -> np.ndarray:
    """(3, 3) the heading frame's axes as columns (forward, left, up) of one frame's points."""
    hips = points[fmt.index("left_hip")] - points[fmt.index("right_hip")]
    left = np.array([hips[0], hips[1], 0.0]) / np.hypot(hips[0], hips[1])
    up = np.array([0.0, 0.0, 1.0])
    return np.column_stack([np.cross(left, up), left, up])


def _sizes(receiver: np.ndarray, fmt) -> tuple[dict[str, float], np.ndarray]:
    """Median segment lengths over the recording and the standing vertex-to-heel height [m],
    and which frames stand (both knees straighter than STANDING_KNEE_DEG)."""
    def point(name: str) -> np.ndarray:
        return receiver[:, fmt.index(name)]

    sizes = {}
    for segment, (a, b) in SEGMENTS.items():
        both = [np.linalg.norm(point(f"{s}_{b}") - point(f"{s}_{a}"), axis=1)
                for s in ("left", "right")]
        sizes[f"{segment}_m"] = float(np.median(np.concatenate(both)))
    knees = [np.degrees(np.arccos(np.clip(np.einsum(
        "ij,ij->i", _unit(point(f"{s}_knee") - point(f"{s}_hip")),
        _unit(point(f"{s}_ankle") - point(f"{s}_knee"))), -1, 1))) for s in ("left", "right")]
    standing = np.maximum(*knees) < STANDING_KNEE_DEG
    heels = np.minimum(point("left_heel")[:, 2], point("right_heel")[:, 2])
    height = point("head")[:, 2] - heels
    sizes["head_to_heel_m"] = float(np.median(height[standing])) if standing.any() else None
    shoulders = (point("left_shoulder")[:, 2] + point("right_shoulder")[:, 2]) / 2 - heels
    sizes["shoulder_height_m"] = (float(np.median(shoulders[standing])) if standing.any()
                                  else None)
    sizes["standing_frames"] = int(standing.sum())
    return {k: (round(v, 3) if isinstance(v, float) else v) for k, v in sizes.items()}, standing


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def derive(data_dir: Path) -> pd.DataFrame:
    """Every handover under ``data_dir``: the figures of those with a transfer, the rest with
    the reason they were dropped."""
    files = sorted(data_dir.rglob("*.pkl"))
    if not files:
        raise SystemExit(f"{data_dir}: no .pkl handover files found (expected the data set's "
                         "data/whole_motions/)")
    rows = []
    for path in files:
        try:
            rows.append({**handover(path), "dropped": ""})
        except TransferError as exc:
            rows.append({"handover": path.stem, "dropped": str(exc)})
        except (KeyError, ValueError, pickle.UnpicklingError) as exc:
            rows.append({"handover": path.stem, "dropped": f"unreadable: {exc}"})
    return pd.DataFrame(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("data_dir", type=Path, help="the folder of the data set's .pkl files")
    parser.add_argument("--output", type=Path, default=OUTPUT, help="CSV to write")
    args = parser.parse_args()
    if not args.data_dir.is_dir():
        print(f"{args.data_dir}: not a folder", file=sys.stderr)
        raise SystemExit(2)
    table = derive(args.data_dir)
    text = f"# source: {SOURCE}\n" + table.to_csv(index=False, lineterminator="\n")
    args.output.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=args.output.parent, delete=False,
                                     suffix=".tmp") as handle:
        handle.write(text)
    os.replace(handle.name, args.output)
    dropped = int((table["dropped"] != "").sum())
    print(f"{len(table) - dropped} handovers used, {dropped} dropped -> {args.output}",
          file=sys.stderr)


if __name__ == "__main__":
    main()
