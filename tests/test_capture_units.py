"""What a file does not say, told from the file or refused: a keypoint file's unit from the
length of its legs (metres, centimetres, millimetres, inches, the CMU database's 1/0.45 inch);
angles and BVH rotations in radians refused in one line naming ``--radians``, which reads them."""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd
import pytest
from cli_run import run_cli

from ergohandover.capture.checks import CANDIDATE_UNITS, LEG_M, infer_unit
from ergohandover.capture.formats import KeypointFormat
from ergohandover.capture.readers import KeypointFileError, Keypoints
from ergohandover.ergonomics.posture import COLUMNS

JOINTS = ("left_hip", "left_knee", "left_ankle", "right_hip", "right_knee", "right_ankle")
FORMAT = KeypointFormat("legs", "two legs", JOINTS, "y", {j: (j,) for j in JOINTS})


def legs(metres: float, per_unit: float, frames: int = 4) -> Keypoints:
    """Two straight legs ``metres`` long (thigh 0.53, shank 0.47 of it), written in a unit of
    ``per_unit`` metres."""
    thigh, shank = 0.53 * metres, 0.47 * metres
    one = np.array([[-0.1, 1.0, 0], [-0.1, 1.0 - thigh, 0.02], [-0.1, 1.0 - thigh - shank, 0],
                    [0.1, 1.0, 0], [0.1, 1.0 - thigh, 0.02], [0.1, 1.0 - thigh - shank, 0]])
    return Keypoints(np.arange(1, frames + 1), np.repeat(one[None], frames, axis=0) / per_unit,
                     FORMAT)


@pytest.mark.parametrize("name", list(CANDIDATE_UNITS))
@pytest.mark.parametrize("leg", [LEG_M[0] + 0.01, 0.85, LEG_M[1] - 0.01])
def test_a_persons_legs_tell_the_files_unit(name, leg):
    per_unit = CANDIDATE_UNITS[name]
    found, metres = infer_unit(legs(leg, per_unit), "f.npy")
    assert (found, metres) == (name, per_unit)


def test_legs_no_unit_makes_a_persons_are_refused_naming_units():
    with pytest.raises(KeypointFileError) as refused:
        infer_unit(legs(0.85, 0.2), "f.npy")  # 4.25 units: 4.25 m, 0.11 m in inches, ...
    message = str(refused.value)
    assert "\n" not in message and message.startswith("f.npy: its unit cannot be told")
    assert "give --units" in message and "4.25 file units long" in message


def posture_file(path, radians: bool) -> pd.DataFrame:
    table = pd.read_csv("examples/postures.csv")
    if radians:
        for column in COLUMNS:
            if column.kind == "angle" and column.name in table:
                table[column.name] = np.radians(table[column.name])
    table.to_csv(path, index=False)
    return table


def test_a_posture_csv_in_radians_is_refused_and_read_with_radians(tmp_path, monkeypatch):
    from pathlib import Path

    monkeypatch.chdir(Path(__file__).resolve().parents[1])
    degrees, radians = tmp_path / "deg.csv", tmp_path / "rad.csv"
    posture_file(degrees, False)
    posture_file(radians, True)
    out = tmp_path / "out.csv"
    done = run_cli("score", "--input", str(radians), "--output", str(out))
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1
    assert re.search(r"rad\.csv: every angle is within ±3\.19 \(the largest, '[a-z_]+', "
                     r"[0-9.]+\): these look like radians; .*--radians", done.stderr)
    assert not out.exists()
    assert run_cli("score", "--input", str(radians), "--output", str(out),
                   "--radians").returncode == 0
    assert run_cli("score", "--input", str(degrees), "--output",
                   str(tmp_path / "d.csv")).returncode == 0
    got, want = pd.read_csv(out), pd.read_csv(tmp_path / "d.csv")
    for score in ("reba", "rula", "paper_postural"):
        assert got[score].tolist() == want[score].tolist()
    assert got["reba"].tolist() == [1, 9, 9]  # not the 1/2/2 radians read as degrees give
    done = run_cli("score", "--items", "-", "--radians", stdin="reba_trunk\n1\n")
    assert done.returncode == 2 and "--radians cannot be used with --items" in done.stderr


def test_a_neutral_file_is_taken_as_given():
    from ergohandover.io.posture_csv import angle_unit_checked

    still = {"trunk_flexion": np.array([0.0, 0.2]), "neck_flexion": np.array([0.1, 0.0])}
    assert angle_unit_checked(still, "f.csv", False) is still
    converted = angle_unit_checked({"trunk_flexion": np.array([math.pi / 2])}, "f.csv", True)
    assert converted["trunk_flexion"][0] == pytest.approx(90.0)
