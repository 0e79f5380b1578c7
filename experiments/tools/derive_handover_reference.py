"""Receiver posture and object location at the moment of transfer in recorded human–human
handovers, as a reference for the twin that receives the box.

Usage: python experiments/tools/derive_handover_reference.py DATA_DIR [--output FILE]
       [--skip-invalid]

Data: the "Handovers@RPL" data set of P. Khanna, M. Björkman, C. Smith, "A Multimodal Data Set
of Human Handovers with Design Implications for Human-Robot Handovers", IEEE RO-MAN 2023,
pp. 1843-1850, doi:10.1109/RO-MAN57019.2023.10309537, arXiv:2304.02154. It is distributed under
the MIT licence at https://github.com/KTH-RPL/handovers_dataset (also
https://github.com/paragkhanna1/dataset). The data are not part of this project. Download them,
unzip the per-set archives (dataset_pairwise/PairN/SettingK/SetM/*.zip) or take the sample
handover, and pass the folder as DATA_DIR.

Input. DATA_DIR is searched recursively for folders holding ``baton_pose_saved.csv``; each one
is a handover. The script reads these files from it (OptiTrack, 120 Hz, z up, metres):
``baton_pose_saved.csv`` and ``{giver,taker}_<segment>_pose_saved.csv`` (columns x, y, z used)
and ``Wrench_{taker,giver}_saved.csv`` (column Fz; grip force = -Fz). Files named
``*metadata*.txt`` anywhere under DATA_DIR (``dataset_pairwise/PairN/metadata.txt``) are parsed
for the participants' sex, age, handedness and stature.

Definitions (one handover; all frames are 0-based row indices after the header):

- Taker onset: first frame where the taker's grip exceeds 2 N.
- Transfer instant: first frame at or after the onset where the taker's grip exceeds the
  giver's (the grip-force crossover). The giver holds the baton from the start of each
  recording, so the crossover is only searched for after the onset.
- Giver release: first frame at or after the onset where the giver's grip is below 1 N (null if
  it never is). The onset and the release bound the transfer.
- Receiver frame, rebuilt at every frame: origin on the taker's hip segment origin horizontally;
  forward = horizontal unit vector from the taker's hip to the giver's hip; left = up x forward
  (the taker's left, right-handed with z up); height = z above the floor (the mocap z = 0).
- Joint centres (assumption): segment origins. UArm origin = shoulder joint, FArm origin =
  elbow, Hand origin = wrist. Baton origin = baton centre.
- Receiving hand: the taker's hand whose wrist is nearer the baton at the transfer instant. If
  the two hand tracks are identical (one hand not tracked; seen in a sample) or a wrist is
  missing, both wrists are discarded and the nearer elbow decides.
- Trunk: hip -> neck vector. Inclination = its angle from vertical, signed + when leaning toward
  the giver; sagittal and lateral components are atan2(forward, up) and atan2(left, up).
- Upper arm: shoulder -> elbow. Elevation from vertical-down, elevation from trunk-down (neck ->
  hip), and sagittal flexion = atan2(forward, down) of the vector (0 = hanging, 90 = horizontal
  forward, negative = behind the body; the sagittal plane is forward-vertical of the frame).
- Elbow flexion: angle between shoulder -> elbow and elbow -> wrist (0 = straight).
- Body sizes: standing heights = median over the first 0.5 s (assumes the taker stands upright
  then); segment lengths and shoulder breadth = median over the whole recording.
- Object: baton height minus the receiving shoulder's / elbow's height at the instant and minus
  the standing shoulder height; forward and lateral offsets from the hip and from the receiving
  shoulder in the receiver frame.

Output: JSON with sorted keys; metres rounded to 1 mm, degrees to 0.1 deg, forces to 0.1 N;
written through a temporary file and os.replace. Bad input (missing folder or file, no
handover, missing column, no transfer found) prints one line on stderr and exits with code 2.
With --skip-invalid, a handover whose files or forces are unusable is reported on stderr and
listed in the output instead of stopping the run.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
from handover_summary import clean, read_metadata, summarise

DEFAULT_OUTPUT = "src/ergohandover/study/validation/handover_reference.json"
PROJECT_ROOT = Path(__file__).resolve().parents[2]
MARKER_FILE = "baton_pose_saved.csv"
RATE_HZ = 120.0
STANDING_S = 0.5
ONSET_N = 2.0
RELEASE_N = 1.0
TAKER_SEGMENTS = ("hip", "chest", "neck", "head", "LUArm", "RUArm", "LFArm", "RFArm", "LHand",
                  "RHand")
SIDES = {"R": "right", "L": "left"}

CITATION = ("P. Khanna, M. Björkman, C. Smith, \"A Multimodal Data Set of Human Handovers with "
            "Design Implications for Human-Robot Handovers\", IEEE RO-MAN 2023, pp. 1843-1850")
DEFINITIONS = (
    "grip force = -Fz of Wrench_taker_saved.csv / Wrench_giver_saved.csv",
    "taker onset = first frame with taker grip > 2 N",
    "transfer frame = first frame at or after the onset with taker grip > giver grip",
    "giver release = first frame at or after the onset with giver grip < 1 N (null if none)",
    "frames are 0-based rows at 120 Hz",
    "receiver frame: origin = taker hip segment origin (horizontal), forward = horizontal unit "
    "vector taker hip -> giver hip, left = up x forward, height = z above floor (m)",
    "assumption: segment origins are joint centres (UArm = shoulder, FArm = elbow, Hand = "
    "wrist); baton origin = baton centre",
    "receiving hand = taker wrist nearer the baton at the transfer frame; nearer elbow if the "
    "hand tracks are identical or missing",
    "trunk = hip -> neck; inclination from vertical signed + toward the giver",
    "upper arm = shoulder -> elbow; elevation from vertical-down and from trunk-down (neck -> "
    "hip); sagittal flexion = atan2(forward, down) in the forward-vertical plane",
    "elbow flexion = angle between shoulder -> elbow and elbow -> wrist (0 = straight)",
    "standing heights = median over the first 0.5 s; segment lengths and shoulder breadth = "
    "median over the recording",
    "object heights relative to the receiving shoulder and elbow at the transfer frame",
    "summary sd = sample standard deviation (ddof 1); null when n < 2",
)


class InputError(Exception):
    """Unusable input; the message names the path and field."""


# ---------------------------------------------------------------------------- reading


def read_columns(path: Path, columns: tuple[str, ...], rows: int | None = None) -> np.ndarray:
    """The named columns of a CSV as a float array; InputError naming the file and field."""
    if not path.is_file():
        raise InputError(f"{path}: file not found")
    try:
        frame = pd.read_csv(path)
    except (OSError, ValueError, pd.errors.ParserError) as exc:
        raise InputError(f"{path}: cannot be read as CSV ({type(exc).__name__})") from None
    frame.columns = [str(c).strip() for c in frame.columns]
    for column in columns:
        if column not in frame.columns:
            raise InputError(f"{path}: missing column '{column}'")
    values = frame[list(columns)].apply(pd.to_numeric, errors="coerce").to_numpy(float)
    if len(values) == 0:
        raise InputError(f"{path}: no data rows")
    if rows is not None and len(values) != rows:
        raise InputError(f"{path}: {len(values)} rows, expected {rows} like {MARKER_FILE}")
    return values


def load_handover(folder: Path) -> dict[str, np.ndarray]:
    baton = read_columns(folder / MARKER_FILE, ("x", "y", "z"))
    rows = len(baton)
    data = {"baton": baton}
    for role in ("taker", "giver"):
        force = read_columns(folder / f"Wrench_{role}_saved.csv", ("Fz",), rows)
        data[f"grip_{role}"] = -force[:, 0]
    data["giver_hip"] = read_columns(folder / "giver_hip_pose_saved.csv", ("x", "y", "z"), rows)
    for segment in TAKER_SEGMENTS:
        data[segment] = read_columns(folder / f"taker_{segment}_pose_saved.csv", ("x", "y", "z"),
                                     rows)
    return data


FILES_USED = (
    [MARKER_FILE, "Wrench_taker_saved.csv", "Wrench_giver_saved.csv", "giver_hip_pose_saved.csv"]
    + [f"taker_{s}_pose_saved.csv" for s in TAKER_SEGMENTS]
)


# ---------------------------------------------------------------------------- geometry


def unit(v: np.ndarray) -> np.ndarray:
    norm = np.linalg.norm(v, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return v / norm


def angle_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle between row vectors a and b (broadcast), degrees."""
    cos = np.sum(unit(a) * unit(b), axis=-1)
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def transfer_frames(
    taker: np.ndarray, giver: np.ndarray, where: Path
) -> tuple[int, int, int | None]:
    """(transfer, taker onset, giver release) frames from the two grip forces."""
    frames = np.arange(len(taker))
    above = taker > ONSET_N
    if not above.any():
        raise InputError(f"{where / 'Wrench_taker_saved.csv'}: taker grip (-Fz) never exceeds "
                         f"{ONSET_N:g} N")
    onset = int(np.argmax(above))
    crossed = (frames >= onset) & (taker > giver)
    if not crossed.any():
        raise InputError(f"{where / 'Wrench_giver_saved.csv'}: taker grip never exceeds the "
                         "giver's (-Fz) after the taker onset")
    released = (frames >= onset) & (giver < RELEASE_N)
    release = int(np.argmax(released)) if released.any() else None
    return int(np.argmax(crossed)), onset, release


def analyse(folder: Path, ident: str) -> dict:
    d = load_handover(folder)
    frame, onset, release = transfer_frames(d["grip_taker"], d["grip_giver"], folder)

    up = np.array([0.0, 0.0, 1.0])
    hip = d["hip"]
    heading = d["giver_hip"] - hip
    heading[:, 2] = 0.0
    fwd = unit(heading)                       # (n, 3) per frame
    left = np.cross(up, fwd)

    def local(point: np.ndarray, f: int) -> np.ndarray:
        """(forward, left, height) of a point in the receiver frame of frame f."""
        rel = point - hip[f]
        return np.array([rel @ fwd[f], rel @ left[f], point[2]])

    shoulder = {s: d[f"{s}UArm"] for s in SIDES}
    elbow = {s: d[f"{s}FArm"] for s in SIDES}
    wrist = {s: d[f"{s}Hand"] for s in SIDES}
    quality = []
    separation = np.linalg.norm(wrist["L"] - wrist["R"], axis=1)
    hands_identical = not np.isfinite(separation).any() or bool(np.nanmax(separation) < 1e-6)
    if hands_identical:
        quality.append("taker_LHand and taker_RHand tracks are identical or missing: wrists, "
                       "forearm lengths and elbow flexion discarded; hand chosen by nearer elbow")
        nan = np.full_like(wrist["L"], np.nan)
        wrist = {"L": nan, "R": nan}

    baton = d["baton"]
    near_wrist = {s: np.linalg.norm(wrist[s][frame] - baton[frame]) for s in SIDES}
    if all(np.isfinite(v) for v in near_wrist.values()):
        hand = min(SIDES, key=lambda s: (near_wrist[s], s))
        chosen_by = "wrist"
    else:
        near_elbow = {s: np.linalg.norm(elbow[s][frame] - baton[frame]) for s in SIDES}
        if not all(np.isfinite(v) for v in near_elbow.values()):
            raise InputError(f"{folder}: taker elbows (FArm) and wrists (Hand) missing at the "
                             f"transfer frame {frame}")
        hand = min(SIDES, key=lambda s: (near_elbow[s], s))
        chosen_by = "elbow"
    other = "L" if hand == "R" else "R"

    # Per-frame angles, then picked at the frames of interest.
    trunk = d["neck"] - hip
    trunk_fwd = np.sum(trunk * fwd, axis=1)
    trunk_left = np.sum(trunk * left, axis=1)
    trunk_angles = {
        "inclination_deg": np.sign(trunk_fwd) * angle_deg(trunk, up),
        "sagittal_flexion_deg": np.degrees(np.arctan2(trunk_fwd, trunk[:, 2])),
        "lateral_bend_left_deg": np.degrees(np.arctan2(trunk_left, trunk[:, 2])),
    }

    def arm_angles(s: str) -> dict[str, np.ndarray]:
        upper = elbow[s] - shoulder[s]
        fore = wrist[s] - elbow[s]
        return {
            "upper_arm_elevation_vertical_deg": angle_deg(upper, -up),
            "upper_arm_elevation_trunk_deg": angle_deg(upper, -trunk),
            "upper_arm_sagittal_flexion_deg": np.degrees(
                np.arctan2(np.sum(upper * fwd, axis=1), -upper[:, 2])),
            "elbow_flexion_deg": angle_deg(upper, fore),
        }

    standing = slice(0, max(1, round(STANDING_S * RATE_HZ)))
    standing_shoulder = float(np.nanmedian(shoulder[hand][standing, 2]))

    def object_figures(f: int) -> dict[str, float]:
        b = baton[f]
        rel_hip = b - hip[f]
        rel_sh = b - shoulder[hand][f]
        return {
            "baton_height_m": b[2],
            "above_shoulder_m": b[2] - shoulder[hand][f][2],
            "above_elbow_m": b[2] - elbow[hand][f][2],
            "above_standing_shoulder_m": b[2] - standing_shoulder,
            "forward_of_hip_m": rel_hip @ fwd[f],
            "forward_of_shoulder_m": rel_sh @ fwd[f],
            "left_of_hip_m": rel_hip @ left[f],
            "left_of_shoulder_m": rel_sh @ left[f],
            "horizontal_distance_hip_m": np.hypot(rel_hip[0], rel_hip[1]),
            "horizontal_distance_shoulder_m": np.hypot(rel_sh[0], rel_sh[1]),
            "wrist_to_baton_m": np.linalg.norm(wrist[hand][f] - b),
            "interpersonal_hip_distance_m": np.linalg.norm(heading[f]),
        }

    body = {
        "shoulder_height_standing_m": standing_shoulder,
        "shoulder_height_standing_other_m": float(np.nanmedian(shoulder[other][standing, 2])),
        "hip_height_standing_m": float(np.nanmedian(hip[standing, 2])),
        "neck_height_standing_m": float(np.nanmedian(d["neck"][standing, 2])),
        "shoulder_breadth_m": float(np.nanmedian(
            np.linalg.norm(shoulder["L"] - shoulder["R"], axis=1))),
    }
    for s in SIDES:
        body[f"upper_arm_length_{s}_m"] = float(np.nanmedian(
            np.linalg.norm(elbow[s] - shoulder[s], axis=1)))
        body[f"forearm_length_{s}_m"] = (float(np.nanmedian(
            np.linalg.norm(wrist[s] - elbow[s], axis=1))) if not hands_identical else None)

    positions_all = {
        "baton": baton, "hip": hip, "chest": d["chest"], "neck": d["neck"], "head": d["head"],
        "giver_hip": d["giver_hip"],
    }
    for s in SIDES:
        positions_all[f"shoulder_{s}"] = shoulder[s]
        positions_all[f"elbow_{s}"] = elbow[s]
        positions_all[f"wrist_{s}"] = wrist[s]
    positions = {}
    for name, pts in positions_all.items():
        p = local(pts[frame], frame)
        positions[name] = {"forward_m": p[0], "left_m": p[1], "height_m": p[2]}

    arms = {"receiving": arm_angles(hand), "other": arm_angles(other)}
    angles = {key: {k: v[frame] for k, v in arm.items()} for key, arm in arms.items()}
    angles["trunk"] = {k: v[frame] for k, v in trunk_angles.items()}

    bounds = {"taker_onset": onset, "giver_release": release}
    at_bounds = {}
    for name, f in bounds.items():
        if f is None:
            at_bounds[name] = None
            continue
        at_bounds[name] = dict(object_figures(f))
        at_bounds[name]["receiving_elbow_flexion_deg"] = arms["receiving"]["elbow_flexion_deg"][f]
        at_bounds[name]["trunk_inclination_deg"] = trunk_angles["inclination_deg"][f]

    return {
        "id": ident,
        "frame": frame,
        "time_s": frame / RATE_HZ,
        "frames_bounds": bounds,
        "grip_at_frame": {"taker_N": d["grip_taker"][frame], "giver_N": d["grip_giver"][frame]},
        "hand": SIDES[hand],
        "hand_chosen_by": chosen_by,
        "positions": positions,
        "body": body,
        "angles": angles,
        "object": object_figures(frame),
        "at_bounds": at_bounds,
        "quality": quality,
        "rows": len(baton),
    }


# ---------------------------------------------------------------------------- metadata

def find_handovers(root: Path) -> list[Path]:
    return sorted({p.parent for p in root.rglob(MARKER_FILE) if p.is_file()})


def build(root: Path, skip_invalid: bool) -> dict:
    if not root.is_dir():
        raise InputError(f"{root}: DATA_DIR not found or not a folder")
    folders = find_handovers(root)
    if not folders:
        raise InputError(f"{root}: no handover folder (one holding {MARKER_FILE}) found")
    handovers, skipped = [], []
    for folder in folders:
        ident = folder.relative_to(root).as_posix() if folder != root else folder.name
        try:
            handovers.append(analyse(folder, ident))
        except InputError as exc:
            if not skip_invalid:
                raise
            print(f"skipped: {exc}", file=sys.stderr)
            skipped.append({"id": ident, "reason": str(exc).replace(str(root), "DATA_DIR")})
    if not handovers:
        raise InputError(f"{root}: no usable handover ({len(skipped)} skipped)")
    handovers.sort(key=lambda h: h["id"])
    source = {
        "dataset": "Handovers@RPL (human-human handovers of a baton; OptiTrack 120 Hz, "
                   "baton with grip force/torque sensors)",
        "citation": CITATION,
        "doi": "10.1109/RO-MAN57019.2023.10309537",
        "arxiv": "2304.02154",
        "url": "https://github.com/KTH-RPL/handovers_dataset",
        "licence": "MIT (Copyright (c) 2022 Parag Khanna)",
        "files_used": FILES_USED,
        "definitions": list(DEFINITIONS),
        "handover_folders": len(folders),
        "skipped": skipped,
        "metadata": read_metadata(root),
        "note": "figures computed from the recordings by this project; not published values",
    }
    return {"source": clean(source), "handovers": clean(handovers),
            "summary": clean(summarise(handovers))}


def write_json(result: dict, output: Path) -> None:
    parent = output.parent if str(output.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{output}: output folder does not exist")
    text = json.dumps(result, indent=1, sort_keys=True, ensure_ascii=False, allow_nan=False) + "\n"
    fd, tmp = tempfile.mkstemp(prefix=f".{output.name}.", suffix=".tmp", dir=parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
        os.replace(tmp, output)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=(
            "Derive the receiver's posture and the object's location at the moment of transfer "
            "from recorded human-human handovers (Handovers@RPL data set: " + CITATION
            + ", doi:10.1109/RO-MAN57019.2023.10309537; MIT licence; get it from "
            "https://github.com/KTH-RPL/handovers_dataset and unzip the per-set archives under "
            "dataset_pairwise/, or use the sample handover folder)."),
        epilog="Definitions and assumptions are in this script's docstring and in the output's "
               "source.definitions. Exit code 2 on bad input.")
    parser.add_argument("data_dir", metavar="DATA_DIR", type=Path,
                        help="folder searched recursively for handover folders (those holding "
                             f"{MARKER_FILE}) and *metadata*.txt files")
    parser.add_argument("--output", type=Path, default=PROJECT_ROOT / DEFAULT_OUTPUT,
                        help=f"JSON file to write (default: {DEFAULT_OUTPUT} in the project)")
    parser.add_argument("--skip-invalid", action="store_true",
                        help="skip (and list) handovers whose files or grip forces are unusable "
                             "instead of stopping")
    args = parser.parse_args(argv)
    try:
        result = build(args.data_dir, args.skip_invalid)
        write_json(result, args.output)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(f"{args.output}: {result['summary']['n']} handover(s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
