"""Keypoint files: the twin's postures written in every file layout read back as the same
points, and every kind of bad file answered with one line naming the file and what is wrong."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from twin_postures import random_twin_postures

from ergohandover.capture.angles import measure
from ergohandover.capture.checks import check_keypoints
from ergohandover.capture.formats import FORMATS, keypoint_format
from ergohandover.capture.placement import place
from ergohandover.capture.readers import KeypointFileError, Keypoints, read_keypoints
from ergohandover.errors import ErgohandoverError
from ergohandover.io.csv_input import InputError

N_POSTURES = 24


@pytest.fixture(scope="module")
def twin():
    """(body, forward kinematics) of random twin postures."""
    body, state, _ = random_twin_postures(N_POSTURES, 7)
    return body, state


@pytest.fixture(scope="module")
def placed(twin):
    """Format name -> the twin's points as its joints, in its own up axis [m]."""
    body, st = twin
    return {name: place(st, body, fmt) for name, fmt in FORMATS.items()}


@pytest.fixture
def here(tmp_path, monkeypatch):
    """Files are named as a user types them: relative to the working folder."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


def wide_table(points: np.ndarray, joints, frames=None) -> pd.DataFrame:
    n = len(points)
    columns = {"frame": np.arange(1, n + 1) if frames is None else frames,
               "note": ["seen"] * n}  # an extra column, ignored
    for j, joint in enumerate(joints):
        for a, axis in enumerate("xyz"):
            columns[f"{joint}_{axis}"] = points[:, j, a]
    return pd.DataFrame(columns)


def long_table(points: np.ndarray, joints, by_index: bool = False) -> pd.DataFrame:
    n, count = points.shape[:2]
    table = pd.DataFrame({
        "frame": np.repeat(np.arange(1, n + 1), count),
        "joint": np.tile(np.arange(count) if by_index else np.array(joints), n),
        "x": points[..., 0].ravel(), "y": points[..., 1].ravel(), "z": points[..., 2].ravel()})
    return table.sample(frac=1.0, random_state=3)  # any row order


def landmark_objects(frame: np.ndarray, visibility=None) -> list[dict]:
    marks = [{"x": float(x), "y": float(y), "z": float(z)} for x, y, z in frame]
    if visibility is not None:
        for mark, v in zip(marks, visibility, strict=True):
            mark["visibility"] = float(v)
    return marks


def assert_same_measures(read: np.ndarray, truth: np.ndarray, fmt) -> None:
    got, want = measure(read, fmt), measure(truth, fmt)
    assert got.keys() == want.keys()
    for column in want:
        np.testing.assert_allclose(got[column], want[column], atol=1e-7, equal_nan=True,
                                   err_msg=column)


# -- round trips -------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(FORMATS))
def test_wide_csv_round_trip(here, placed, name):
    fmt, points = FORMATS[name], placed[name]
    frames = np.arange(101, 101 + len(points))
    wide_table(points, fmt.joints, frames).to_csv("pose.csv", index=False)
    kp = read_keypoints("pose.csv", fmt)
    assert isinstance(kp, Keypoints) and kp.fmt is fmt
    np.testing.assert_array_equal(kp.frames, frames)
    np.testing.assert_allclose(kp.points, points, rtol=0, atol=1e-12)
    assert not check_keypoints(kp, fmt.up, "error", "pose.csv").any()
    assert_same_measures(kp.points, points, fmt)


@pytest.mark.parametrize("name", sorted(FORMATS))
@pytest.mark.parametrize("by_index", [False, True])
def test_long_csv_round_trip(here, placed, name, by_index):
    fmt, points = FORMATS[name], placed[name]
    long_table(points, fmt.joints, by_index).to_csv("pose.CSV", index=False)
    kp = read_keypoints("pose.CSV", fmt)
    np.testing.assert_array_equal(kp.frames, np.arange(1, len(points) + 1))
    np.testing.assert_allclose(kp.points, points, rtol=0, atol=1e-12)
    assert_same_measures(kp.points, points, fmt)


@pytest.mark.parametrize("name", sorted(FORMATS))
def test_npy_and_npz_round_trip(here, placed, name):
    fmt, points = FORMATS[name], placed[name]
    np.save("pose.npy", points)
    np.savez("pose.npz", keypoints=points.astype(np.float32), fps=np.array(30.0))
    np.savez_compressed("only.npz", poses=points)
    for path, tolerance in (("pose.npy", 0.0), ("pose.npz", 1e-6), ("only.npz", 0.0)):
        kp = read_keypoints(path, fmt)
        np.testing.assert_array_equal(kp.frames, np.arange(1, len(points) + 1))
        np.testing.assert_allclose(kp.points, points, rtol=0, atol=tolerance, err_msg=path)
        assert kp.points.dtype == np.float64
    np.save("one.npy", points[3])  # (J, 3): one frame
    kp = read_keypoints("one.npy", fmt)
    assert kp.points.shape == (1, len(fmt.joints), 3)
    np.testing.assert_array_equal(kp.points[0], points[3])
    assert_same_measures(read_keypoints("pose.npy", fmt).points, points, fmt)


FRAME_SHAPES = {
    "list": lambda marks: marks,
    "pose_world_landmarks": lambda marks: {"pose_world_landmarks": marks},
    "worldLandmarks": lambda marks: {"worldLandmarks": marks},
    "protobuf": lambda marks: {"world_landmarks": {"landmark": marks}},
    "tasks": lambda marks: {"pose_world_landmarks": [marks]},
}


@pytest.mark.parametrize("shape", sorted(FRAME_SHAPES))
def test_mediapipe_json_round_trip(here, placed, shape):
    fmt, points = FORMATS["mediapipe33"], placed["mediapipe33"]
    frames = [FRAME_SHAPES[shape](landmark_objects(frame, np.full(len(frame), 0.9)))
              for frame in points]
    Path("pose.json").write_text(json.dumps(frames))
    kp = read_keypoints("pose.json", fmt)
    np.testing.assert_array_equal(kp.frames, np.arange(1, len(points) + 1))
    np.testing.assert_array_equal(kp.points, points)
    assert_same_measures(kp.points, points, fmt)


def test_one_json_frame_not_in_a_list(here, placed):
    fmt, points = FORMATS["mediapipe33"], placed["mediapipe33"]
    Path("one.json").write_text(json.dumps({"worldLandmarks": landmark_objects(points[0])}))
    Path("bare.json").write_text(json.dumps(landmark_objects(points[1])))
    np.testing.assert_array_equal(read_keypoints("one.json", fmt).points, points[:1])
    np.testing.assert_array_equal(read_keypoints("bare.json", fmt).points, points[1:2])


def test_units_divide_to_metres(here, placed):
    fmt, points = FORMATS["h36m17"], placed["h36m17"]
    for units, scale in (("cm", 100.0), ("mm", 1000.0)):
        np.save(f"pose_{units}.npy", points * scale)
        kp = read_keypoints(f"pose_{units}.npy", fmt, units=units)
        np.testing.assert_allclose(kp.points, points, rtol=1e-12, atol=1e-15)
        check_keypoints(kp, fmt.up, "error", f"pose_{units}.npy")


# -- missing points ----------------------------------------------------------------------------


def test_missing_points_in_each_layout_are_nan(here, placed):
    fmt = FORMATS["mediapipe33"]
    points = placed["mediapipe33"]
    gaps = np.zeros(points.shape[:2], dtype=bool)
    gaps[2, 5] = gaps[7, 0] = gaps[7, 31] = True
    wide = wide_table(points, fmt.joints).astype(object)
    for i, j in np.argwhere(gaps):
        wide.loc[i, f"{fmt.joints[j]}_y"] = ""  # one empty cell: the whole point is missing
    wide.to_csv("wide.csv", index=False)
    long = long_table(points, fmt.joints)
    keep = ~gaps[long["frame"].to_numpy() - 1, [fmt.index(j) for j in long["joint"]]]
    long[keep].to_csv("long.csv", index=False)  # unlisted joints are missing
    visibility = np.where(gaps, 0.2, 0.95)
    Path("pose.json").write_text(json.dumps(
        [landmark_objects(f, v) for f, v in zip(points, visibility, strict=True)]))
    for path in ("wide.csv", "long.csv", "pose.json"):
        kp = read_keypoints(path, fmt)
        np.testing.assert_array_equal(np.isnan(kp.points).all(axis=2), gaps, err_msg=path)
        assert not np.isnan(kp.points[~gaps]).any()
        np.testing.assert_array_equal(kp.points[~gaps], points[~gaps])
        seen = check_keypoints(kp, fmt.up, "unseen", path)
        np.testing.assert_array_equal(seen, gaps.any(axis=1))


def test_a_json_frame_without_a_pose_is_a_frame_of_missing_points(here, placed):
    fmt, points = FORMATS["mediapipe33"], placed["mediapipe33"]
    frames = [landmark_objects(f) for f in points[:4]]
    frames[1], frames[2] = [], {"pose_world_landmarks": None}
    Path("pose.json").write_text(json.dumps(frames))
    kp = read_keypoints("pose.json", fmt, min_visibility=0.0)
    assert np.isnan(kp.points[1:3]).all() and not np.isnan(kp.points[[0, 3]]).any()
    with pytest.raises(KeypointFileError, match=r"^pose\.json: frame 2 has no points"):
        check_keypoints(kp, fmt.up, "unseen", "pose.json")


def test_a_missing_point_names_the_files_frame_number(here, placed):
    fmt, points = FORMATS["coco17"], placed["coco17"].copy()
    points[4, fmt.index("left_wrist")] = np.nan
    kp = Keypoints(np.arange(10, 10 + len(points)), points, fmt)
    message = one_line(lambda: check_keypoints(kp, fmt.up, "error", "walk.npy"))
    assert message.startswith("walk.npy: frame 14, joint 'left_wrist' is missing")
    assert "--missing unseen" in message and "1 of 24 frames" in message
    np.testing.assert_array_equal(check_keypoints(kp, fmt.up, "unseen", "walk.npy"),
                                  np.arange(len(points)) == 4)


def test_check_accepts_every_format_in_its_own_up_axis_and_others(placed, twin):
    body, st = twin
    for name, fmt in FORMATS.items():
        kp = Keypoints(np.arange(1, N_POSTURES + 1), placed[name], fmt)
        assert not check_keypoints(kp, fmt.up, "error", "f").any()
        for up in ("x", "-z"):
            kp = Keypoints(kp.frames, place(st, body, fmt, up), fmt)
            assert not check_keypoints(kp, up, "error", "f").any()


# -- bad input ---------------------------------------------------------------------------------


def one_line(call) -> str:
    """The message of the KeypointFileError ``call`` raises; it must be one line."""
    with pytest.raises(KeypointFileError) as info:
        call()
    message = str(info.value)
    assert "\n" not in message and message.strip() == message, message
    assert isinstance(info.value, InputError) and isinstance(info.value, ErgohandoverError)
    return message


def read(path: str, name: str = "coco17", **kwargs):
    return lambda: read_keypoints(path, keypoint_format(name), **kwargs)


def test_unknown_extension(here, placed):
    Path("pose.txt").write_text("1 2 3\n")
    message = one_line(read("pose.txt"))
    assert message.startswith("pose.txt has extension '.txt'")
    assert all(ext in message for ext in (".csv", ".npy", ".npz", ".json"))
    Path("walk.bvh").write_text("HIERARCHY\n")
    assert "--format bvh" in one_line(read("walk.bvh"))


def test_bad_units(here, placed):
    np.save("pose.npy", placed["coco17"])
    message = one_line(read("pose.npy", units="inch"))
    assert message.startswith("pose.npy: units 'inch'") and "m, cm, mm" in message


def test_a_file_that_does_not_exist(here):
    assert one_line(read("nowhere.csv")) == "nowhere.csv does not exist"


def test_wrong_joint_count_in_npy(here, placed):
    np.save("pose.npy", np.zeros((5, 25, 3)))
    message = one_line(read("pose.npy"))
    assert message.startswith("pose.npy: every frame has 25 joints; format coco17 has 17")
    assert "(5, 25, 3)" in message
    np.save("flat.npy", np.zeros((5, 17, 2)))
    message = one_line(read("flat.npy"))
    assert "shape (5, 17, 2)" in message and "(frames, 17, 3)" in message


def test_wrong_joint_count_in_long_csv(here, placed):
    points = np.concatenate([placed["coco17"], np.zeros((N_POSTURES, 8, 3))], axis=1)
    long_table(points, None, by_index=True).to_csv("pose.csv", index=False)
    message = one_line(read("pose.csv"))
    assert message.startswith("pose.csv: frame ")
    assert "joint index 24 (so at least 25 joints); format coco17 has 17 (indices 0-16" \
        in message


def test_wrong_joint_count_in_json(here, placed):
    points = placed["mediapipe33"]
    frames = [landmark_objects(f) for f in points[:4]]
    frames[2] = frames[2][:25]
    Path("pose.json").write_text(json.dumps(frames))
    message = one_line(read("pose.json", "mediapipe33"))
    assert message.startswith("pose.json: frame 3 has 25 joints; format mediapipe33 has 33")


def test_missing_joint_column_in_wide_csv(here, placed):
    fmt = FORMATS["coco17"]
    wide_table(placed["coco17"], fmt.joints).drop(columns=["left_elbow_x"]).to_csv(
        "pose.csv", index=False)
    message = one_line(read("pose.csv"))
    assert message.startswith("pose.csv has no column 'left_elbow_x'")
    assert "<joint>_x" in message


def test_unknown_joint_in_long_csv(here, placed):
    table = long_table(placed["coco17"], FORMATS["coco17"].joints).sort_index()
    table.loc[5, "joint"] = "left_elbw"
    table.to_csv("pose.csv", index=False)
    message = one_line(read("pose.csv"))
    assert message.startswith("pose.csv: row 6, column 'joint': 'left_elbw' is not a joint of "
                              "format coco17")


def test_duplicate_joint_in_a_long_csv_frame(here, placed):
    table = long_table(placed["coco17"], FORMATS["coco17"].joints).sort_index()
    table.loc[17 + 3, "joint"] = "nose"  # frame 2's fourth row repeats its first joint
    table.to_csv("pose.csv", index=False)
    message = one_line(read("pose.csv"))
    assert message.startswith("pose.csv: frame 2 lists joint 'nose' twice (rows 18 and 21")


def test_non_numeric_cell(here, placed):
    fmt = FORMATS["coco17"]
    table = wide_table(placed["coco17"], fmt.joints).astype(object)
    table.loc[2, "nose_y"] = "1,52"
    table.to_csv("pose.csv", index=False)
    message = one_line(read("pose.csv"))
    assert message.startswith("pose.csv: row 3, column 'nose_y': '1,52' is not a number")


def test_npz_with_two_arrays_and_no_keypoints_key(here, placed):
    np.savez("pose.npz", poses=placed["coco17"], scores=np.ones(N_POSTURES))
    message = one_line(read("pose.npz"))
    assert message.startswith("pose.npz holds 2 arrays (poses, scores)")
    assert "'keypoints'" in message


def test_json_that_is_not_a_list_of_frames(here):
    Path("pose.json").write_text("42")
    message = one_line(read("pose.json", "mediapipe33"))
    assert message.startswith("pose.json holds a number: expected a list of frames")
    Path("frames.json").write_text(json.dumps([{"keypoints": []}]))
    message = one_line(read("frames.json", "mediapipe33"))
    assert message.startswith("frames.json: frame 1 is an object without pose_world_landmarks")
    Path("broken.json").write_text("[{")
    assert one_line(read("broken.json", "mediapipe33")).startswith("broken.json is not valid "
                                                                   "JSON")


def test_json_landmark_without_x(here, placed):
    frames = [landmark_objects(f) for f in placed["mediapipe33"][:3]]
    del frames[1][4]["x"]
    Path("pose.json").write_text(json.dumps(frames))
    message = one_line(read("pose.json", "mediapipe33"))
    assert message.startswith("pose.json: frame 2, landmark 4 (right_eye_inner) has no 'x'")


def keypoints(points: np.ndarray, name: str = "coco17") -> Keypoints:
    return Keypoints(np.arange(1, len(points) + 1), points, FORMATS[name])


def test_infinite_value(placed):
    points = placed["coco17"].copy()
    points[6, FORMATS["coco17"].index("right_knee"), 1] = np.inf
    message = one_line(lambda: check_keypoints(keypoints(points), "-y", "unseen", "run.npy"))
    assert message.startswith("run.npy: frame 7, joint 'right_knee' has an infinite coordinate")


def test_missing_point_is_an_error_unless_unseen(placed):
    points = placed["coco17"].copy()
    points[3, FORMATS["coco17"].index("left_hip")] = np.nan
    message = one_line(lambda: check_keypoints(keypoints(points), "-y", "error", "run.npy"))
    assert message.startswith("run.npy: frame 4, joint 'left_hip' is missing")
    assert "--missing unseen scores such frames with the columns those points decide as " \
        "unseen" in message


def test_frame_without_points_is_always_an_error(placed):
    points = placed["coco17"].copy()
    points[9] = np.nan
    for missing in ("error", "unseen"):
        message = one_line(lambda m=missing: check_keypoints(keypoints(points), "-y", m,
                                                             "run.npy"))
        assert message.startswith("run.npy: frame 10 has no points")


def test_no_frames():
    empty = keypoints(np.zeros((0, 17, 3)))
    assert one_line(lambda: check_keypoints(empty, "-y", "unseen", "run.npy")) == \
        "run.npy has no frames"


def test_a_40_m_tall_body(here, placed):
    points = placed["coco17"] * 30
    height = np.median(np.ptp(points[..., 1], axis=1))
    assert 30 < height < 50
    message = one_line(lambda: check_keypoints(keypoints(points), "-y", "unseen", "run.npy"))
    assert message.startswith(f"run.npy: the body is {height:.3g} m tall read as --units m (the "
                              f"median extent of its points along the up axis y): expected "
                              f"0.3-3 m")
    # The unit it suggests makes the body 1.7 m tall: near the 1/30 it was scaled by (a hint:
    # COCO-17's points stop short of the head's top).
    suggested = re.search(r"\(--units ([\d.e-]+);", message).group(1)
    assert float(suggested) == pytest.approx(1.7 / height, rel=1e-2)
    assert 1 / 30 < float(suggested) < 1.5 / 30
    assert message.endswith("m, cm and mm are 1, 0.01 and 0.001)")
    np.save("run.npy", points)
    kp = read_keypoints("run.npy", FORMATS["coco17"], units=suggested)
    check_keypoints(kp, "-y", "unseen", "run.npy", suggested)  # now the size of a person


def test_a_height_just_outside_the_range_is_never_printed_inside_it(placed):
    points = placed["coco17"]
    height = np.median(np.ptp(points[..., 1], axis=1))
    tiny = points * (0.29999 / height)
    message = one_line(lambda: check_keypoints(keypoints(tiny), "-y", "unseen", "run.npy"))
    assert "the body is 0.29999 m tall" in message


def test_a_unit_may_be_a_number_of_metres(here, placed):
    fmt, points = FORMATS["h36m17"], placed["h36m17"]
    np.save("inches.npy", points / 0.0254)
    kp = read_keypoints("inches.npy", fmt, units="0.0254")
    np.testing.assert_allclose(kp.points, points, rtol=1e-12, atol=1e-12)
    for bad in ("0", "-1", "inch", "nan"):
        assert "are not allowed (use m, cm, mm, or the metres one unit" in one_line(
            lambda bad=bad: read_keypoints("inches.npy", fmt, units=bad))


def test_upside_down_body(placed):
    message = one_line(lambda: check_keypoints(keypoints(placed["coco17"]), "y", "unseen",
                                               "run.npy"))
    assert message.startswith("run.npy: the body is upside down along the up axis 'y'")
    assert message.endswith("is the up axis '-y'? (--up)")


def test_body_lying_across_the_up_axis(twin):
    body, st = twin
    fmt = FORMATS["coco17"]
    near_rest = st.model.forward(0.2 * st.q)  # arms near the sides: a lying body is flat
    lying = place(near_rest, body, fmt, "z")
    assert not check_keypoints(keypoints(lying), "z", "unseen", "run.npy").any()
    message = one_line(lambda: check_keypoints(keypoints(lying), "y", "unseen", "run.npy"))
    assert message.startswith("run.npy: the body lies across the up axis 'y'")
    assert message.endswith("give the axis that points up (--up x|-x|y|-y|z|-z)")


def test_bad_missing_choice(placed):
    message = one_line(lambda: check_keypoints(keypoints(placed["coco17"]), "-y", "skip",
                                               "run.npy"))
    assert "'skip'" in message and "error or unseen" in message
