"""BVH files: the twin's postures written as BVH read back as the twin's own angles, the
landmarks of CMU-, Mixamo- and Motive-named files, the forward kinematics of hand-written files,
and every kind of bad file answered with one line."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from twin_postures import random_twin_postures

from ergohandover.capture.angles import measure
from ergohandover.capture.bvh import axis_rotation, parse_bvh, read_bvh
from ergohandover.capture.bvh_write import write_bvh, zxy_angles, zxy_matrix
from ergohandover.capture.checks import check_keypoints
from ergohandover.capture.placement import to_axes
from ergohandover.capture.readers import KeypointFileError
from ergohandover.capture.rigs import RIGS
from ergohandover.capture.twin_bvh import twin_bvh, twin_joints
from ergohandover.twin.anthropometry import BodySpec

N_POSTURES = 60
MEASURED = (
    "trunk_flexion", "trunk_side_bend", "trunk_twist", "neck_flexion", "neck_side_bend",
    *(f"{side}_{name}" for side in ("left", "right") for name in (
        "knee_flexion", "upper_arm_flexion", "upper_arm_abduction", "upper_arm_rotation",
        "elbow_flexion", "shoulder_raise", "wrist_flexion", "wrist_deviation", "wrist_twist")),
)
"""The columns a twin BVH file measures as the twin's own angles."""


@pytest.fixture(scope="module")
def twin():
    """(body, forward kinematics, the twin's own Posture columns) of random postures."""
    return random_twin_postures(N_POSTURES, 11)


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def neutral_clavicle(body: BodySpec) -> float:
    """The body's own clavicle slope at rest [deg] (angles' constant is rounded)."""
    s = body.segments()
    return math.degrees(math.atan2(-s.shoulder_drop, s.clavicle_length))


def angle_error(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs((a - b + 180.0) % 360.0 - 180.0)


# -- rotations ---------------------------------------------------------------------------------


def test_zxy_angles_invert_zxy_matrix_including_gimbal_lock():
    rng = np.random.default_rng(0)
    angles = np.column_stack([rng.uniform(-180, 180, 200), rng.uniform(-90, 90, 200),
                              rng.uniform(-180, 180, 200)])
    angles[:5, 1] = 90.0
    angles[5:10, 1] = -90.0
    matrices = zxy_matrix(angles)
    np.testing.assert_allclose(zxy_matrix(zxy_angles(matrices)), matrices, atol=1e-12)
    np.testing.assert_allclose(zxy_angles(matrices)[10:], angles[10:], atol=1e-9)
    np.testing.assert_allclose(axis_rotation(0, 90.0) @ [0, 1, 0], [0, 0, 1], atol=1e-15)


# -- the twin's round trip ---------------------------------------------------------------------


def test_twin_bvh_measures_the_twins_own_angles(here, twin):
    body, st, truth = twin
    Path("twin.bvh").write_text(twin_bvh(st, body))
    kp = read_bvh("twin.bvh")
    assert kp.fmt.name == "bvh" and kp.fmt.up == "y"
    np.testing.assert_array_equal(kp.frames, np.arange(1, N_POSTURES + 1))
    assert not check_keypoints(kp, "y", "error", "twin.bvh").any()
    got = measure(kp.points, kp.fmt, "y", neutral_clavicle_deg=neutral_clavicle(body))
    for column in MEASURED:
        seen = np.isfinite(got[column])
        assert seen.sum() >= N_POSTURES // 2, column
        assert angle_error(got[column][seen], truth[column][seen]).max() < 1e-6, column
    # Where the elbow is straight the arm's rotation is unseen, not wrong.
    straight = truth["left_elbow_flexion"] < 15.0
    np.testing.assert_array_equal(np.isnan(got["left_upper_arm_rotation"]), straight)


def test_twin_bvh_joints_are_the_twins_points(here, twin):
    body, st, _ = twin
    Path("twin.bvh").write_text(twin_bvh(st, body))
    kp = read_bvh("twin.bvh")
    joints, ends = twin_joints(body)
    names = [j[0] for j in joints] + [f"{joint}_End" for joint in ends]
    want = [st.point(link, offset) for _, _, link, offset, _ in joints]
    want += [st.point(link, offset) for link, offset in ends.values()]
    assert sorted(kp.fmt.joints) == sorted(names)
    got = kp.points[:, [kp.fmt.index(n) for n in names]]
    np.testing.assert_allclose(got, to_axes(np.stack(want, axis=1), "y"), rtol=0, atol=1e-8)


@pytest.mark.parametrize("up", ["z", "-x"])
def test_twin_bvh_in_another_up_axis(here, twin, up):
    body, st, truth = twin
    Path("twin.bvh").write_text(twin_bvh(st, body, up=up))
    kp = read_bvh("twin.bvh")
    got = measure(kp.points, kp.fmt, up, neutral_clavicle_deg=neutral_clavicle(body))
    for column in ("trunk_flexion", "neck_side_bend", "right_upper_arm_abduction",
                   "left_wrist_deviation"):
        assert angle_error(got[column], truth[column]).max() < 1e-6, column


def test_units_cm_round_trip(here, twin):
    body, st, _ = twin
    Path("m.bvh").write_text(twin_bvh(st, body))
    Path("cm.bvh").write_text(twin_bvh(st, body, units="cm"))
    metres = read_bvh("m.bvh")
    centimetres = read_bvh("cm.bvh", units="cm")
    np.testing.assert_allclose(centimetres.points, metres.points, rtol=0, atol=1e-9)
    assert "OFFSET 8.289166" in Path("cm.bvh").read_text()
    message = one_line(lambda: check_keypoints(read_bvh("cm.bvh"), "y", "unseen", "cm.bvh"))
    assert message.startswith("cm.bvh: the body is ") and "(--units 0.01" in message


def test_writer_puts_joints_depth_first_whatever_their_order(here):
    # Given breadth first: the file lists a, b, c, then d under c.
    names, parents = ["root", "c", "a", "d"], [-1, 0, 0, 1]
    offsets = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    angles = np.zeros((2, 4, 3))
    angles[1, 1] = (0.0, 0.0, 90.0)  # c turns 90° about y: d's offset z -> x
    write_bvh("tree.bvh", names, parents, offsets, angles, [[0, 0, 0], [5, 0, 0]],
              end_sites={2: (0, 2, 0)})
    kp = parse_bvh("tree.bvh")
    assert kp.names == ("root", "c", "d", "a", "a_End") and kp.parents == (-1, 0, 1, 0, 3)
    assert kp.frame_time == pytest.approx(1 / 30)
    np.testing.assert_allclose(kp.points[0], [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 1, 0],
                                              [0, 3, 0]], atol=1e-12)
    np.testing.assert_allclose(kp.points[1, 2], [7, 0, 0], atol=1e-9)


# -- hand-written files ------------------------------------------------------------------------


def block(name: str, offset: str, body: str = "", kind: str = "JOINT",
          channels: str = "CHANNELS 3 Zrotation Xrotation Yrotation") -> str:
    return f"{kind} {name}\n{{\nOFFSET {offset}\n{channels}\n{body}}}\n"


def end(offset: str) -> str:
    return f"End Site\n{{\nOFFSET {offset}\n}}\n"


def motion(channels: int, rows: list[list[float]] | None = None) -> str:
    rows = rows or [[0.0] * channels]
    lines = "\n".join(" ".join(str(v) for v in row) for row in rows)
    return f"MOTION\nFrames: {len(rows)}\nFrame Time: 0.0083333\n{lines}\n"


def cmu_text() -> str:
    """A CMU-named skeleton (LowerBack, Spine1, Neck1, LFingerBase, LThumb, ...), inches-like
    numbers, all rotations zero."""
    def leg(s: str, k: float) -> str:
        return block(f"{s}UpLeg", f"{k * 1.4} -1.1 0", block(
            f"{s}Leg", "0 -7.5 0", block(f"{s}Foot", "0 -7.3 0", block(
                f"{s}ToeBase", "0 -0.5 2.3", end("0 0 1")))))

    def arm(s: str, k: float) -> str:
        short = s[0]
        return block(f"{s}Shoulder", f"{k * 0.5} 0.9 0", block(
            f"{s}Arm", f"{k * 2.5} 0 0", block(f"{s}ForeArm", "0 -4.9 0", block(
                f"{s}Hand", "0 -3.6 0",
                block(f"{s}FingerBase", "0 -0.7 0", block(f"{s}HandIndex1", "0 -0.6 0",
                                                          end("0 -0.5 0")))
                + block(f"{short}Thumb", f"{k * 0.3} -0.4 0.3", end("0 -0.5 0"))))))

    spine = block("LowerBack", "0 0 0", block("Spine", "0 2 0", block(
        "Spine1", "0 2 0",
        block("Neck", "0 1.7 0", block("Neck1", "0 1.1 0", block("Head", "0 1.1 0",
                                                                 end("0 1.8 0"))))
        + arm("Left", 1.0) + arm("Right", -1.0))))
    hips = block("Hips", "0 0 0", leg("Left", 1.0) + leg("Right", -1.0) + spine, "ROOT",
                 "CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation")
    channels = 6 + 3 * (hips.count("JOINT"))
    return "HIERARCHY\n" + hips + motion(channels, [[0, 17, 0] + [0.0] * (channels - 3)])


def test_cmu_named_file_gives_cmu_landmarks(here):
    Path("cmu.bvh").write_text(cmu_text())
    kp = read_bvh("cmu.bvh", units="m")
    marks = {k: v[0] for k, v in kp.fmt.landmarks.items()}
    expected = {
        "left_hip": "LeftUpLeg", "right_hip": "RightUpLeg", "left_knee": "LeftLeg",
        "right_knee": "RightLeg", "left_ankle": "LeftFoot", "right_ankle": "RightFoot",
        "spine": "Spine1", "neck_base": "Neck", "head_top": "Head_End",
        "left_clavicle": "LeftShoulder", "right_clavicle": "RightShoulder",
        "left_shoulder": "LeftArm", "right_shoulder": "RightArm", "left_elbow": "LeftForeArm",
        "right_elbow": "RightForeArm", "left_wrist": "LeftHand", "right_wrist": "RightHand",
        "left_hand": "LeftFingerBase", "right_hand": "RightFingerBase",
        "left_thumb": "LThumb", "right_thumb": "RThumb"}
    assert marks == expected
    # Upright, arms hanging, elbows straight: the knees and elbows are straight, the trunk
    # upright; the position channels lift the whole body.
    got = measure(kp.points, kp.fmt, "y")
    for column in ("left_knee_flexion", "right_elbow_flexion", "trunk_flexion",
                   "left_upper_arm_flexion", "neck_flexion"):
        assert abs(got[column][0]) < 1e-9, column
    assert kp.points[0, kp.fmt.index("Head_End"), 1] == pytest.approx(17 + 2 + 2 + 1.7 + 1.1
                                                                       + 1.1 + 1.8)


def motive_text() -> str:
    """An OptiTrack Motive-named skeleton (Hip, Ab, Chest, LUArm, LFArm, LThigh, ...) in cm."""
    def side(s: str, k: float) -> tuple[str, str]:
        leg = block(f"{s}Thigh", f"{k * 9} 0 0", block(f"{s}Shin", "0 -42 0", block(
            f"{s}Foot", "0 -41 0", block(f"{s}Toe", "0 -7 13", end("0 0 4")))))
        arm = block(f"{s}Shoulder", f"{k * 3} 18 0", block(f"{s}UArm", f"{k * 16} 0 0", block(
            f"{s}FArm", f"{k * 28} 0 0", block(f"{s}Hand", f"{k * 25} 0 0",
                                                end(f"{k * 18} 0 0")))))
        return leg, arm

    (left_leg, left_arm), (right_leg, right_arm) = side("L", 1.0), side("R", -1.0)
    chest = block("Chest", "0 20 0", block("Neck", "0 21 0", block("Head", "0 10 0",
                                                                  end("0 20 0")))
                  + left_arm + right_arm)
    hip = block("Hip", "0 0 0", left_leg + right_leg + block("Ab", "0 10 0", chest), "ROOT",
                "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation")
    channels = 6 + 3 * hip.count("JOINT")
    return "HIERARCHY\n" + hip + motion(channels, [[0, 95, 0] + [0.0] * (channels - 3)])


def test_motive_named_file_gives_motive_landmarks(here):
    Path("motive.bvh").write_text(motive_text())
    kp = read_bvh("motive.bvh", units="cm")
    marks = {k: v[0] for k, v in kp.fmt.landmarks.items()}
    assert marks == {
        "left_hip": "LThigh", "right_hip": "RThigh", "left_knee": "LShin",
        "right_knee": "RShin", "left_ankle": "LFoot", "right_ankle": "RFoot",
        "spine": "Chest", "neck_base": "Neck", "head_top": "Head_End",
        "left_clavicle": "LShoulder", "right_clavicle": "RShoulder",
        "left_shoulder": "LUArm", "right_shoulder": "RUArm", "left_elbow": "LFArm",
        "right_elbow": "RFArm", "left_wrist": "LHand", "right_wrist": "RHand",
        "left_hand": "LHand_End", "right_hand": "RHand_End"}
    check_keypoints(kp, "y", "error", "motive.bvh")
    # T-pose: arms straight out to the sides, in metres.
    got = measure(kp.points, kp.fmt, "y")
    assert got["left_upper_arm_abduction"][0] == pytest.approx(90.0)
    assert got["right_upper_arm_abduction"][0] == pytest.approx(90.0)
    assert got["left_elbow_flexion"][0] == pytest.approx(0.0, abs=1e-9)
    np.testing.assert_allclose(kp.points[0, kp.fmt.index("LHand")], [0.72, 1.43, 0.0],
                               atol=1e-12)


def test_mixamo_names_lose_their_namespace(here):
    names = ["mixamorig:Hips", "mixamorig:LeftUpLeg", "mixamorig:LeftLeg", "mixamorig:LeftFoot",
             "mixamorig:RightUpLeg", "mixamorig:RightLeg", "mixamorig:RightFoot",
             "mixamorig:Spine", "mixamorig:Spine1", "mixamorig:Spine2", "mixamorig:Neck",
             "mixamorig:Head", "mixamorig:HeadTop_End"]
    parents = [-1, 0, 1, 2, 0, 4, 5, 0, 7, 8, 9, 10, 11]
    for s in ("Left", "Right"):
        base = len(names)
        names += [f"mixamorig:{s}{n}" for n in ("Shoulder", "Arm", "ForeArm", "Hand",
                                                "HandMiddle1", "HandIndex1", "HandPinky1",
                                                "HandThumb1")]
        parents += [9, base, base + 1, base + 2, base + 3, base + 3, base + 3, base + 3]
    offsets = np.random.default_rng(3).uniform(-1, 1, (len(names), 3))
    write_bvh("mixamo.bvh", names, parents, offsets, np.zeros((1, len(names), 3)),
              [[0, 0, 0]])
    kp = read_bvh("mixamo.bvh")
    assert kp.fmt.joints[:3] == ("Hips", "LeftUpLeg", "LeftLeg")
    marks = {k: v[0] for k, v in kp.fmt.landmarks.items()}
    assert marks["spine"] == "Spine1" and marks["head_top"] == "HeadTop_End"
    assert marks["left_hand"] == "LeftHandMiddle1" and marks["right_index"] == "RightHandIndex1"
    assert marks["right_pinky"] == "RightHandPinky1" and marks["left_thumb"] == "LeftHandThumb1"


def test_rotation_channels_turn_in_the_order_listed(here):
    text = ("HIERARCHY\n" + block(
        "root", "1 2 3", block("child", "0 1 0", end("0 0 0"),
                               channels="CHANNELS 3 Xposition Yposition Zposition"),
        "ROOT", "CHANNELS 6 Xposition Yposition Zposition Xrotation Yrotation Zrotation")
            + motion(9, [[10, 0, 0, 90, 90, 0, 0, 0, 0], [0, 0, 0, 90, 90, 0, 0, 0, 2]]))
    Path("order.bvh").write_text(text)
    kp = parse_bvh("order.bvh")
    # R = Rx(90) @ Ry(90): the child's offset (0, 1, 0) goes to (0, 0, 1); the other order
    # (Ry @ Rx) would put it at (1, 0, 0).
    np.testing.assert_allclose(kp.points[0, 0], [11, 2, 3], atol=1e-12)
    np.testing.assert_allclose(kp.points[0, 1], [11, 2, 4], atol=1e-12)
    # A non-root joint's position channels add to its offset in the parent's frame:
    # Rx(90) @ Ry(90) @ (0, 1, 2) = (2, 0, 1).
    np.testing.assert_allclose(kp.points[1, 1], [1 + 2, 2, 3 + 1], atol=1e-12)


def test_rigs_are_data_with_both_sides():
    rigs = {rig.name: rig for rig in RIGS}
    assert rigs["OptiTrack Motive"].landmarks["right_elbow"] == ("RFArm",)
    assert rigs["Mixamo"].landmarks["right_thumb"] == ("RightHandThumb1",)
    assert rigs["Blender Rigify"].landmarks["right_hip"] == ("DEF-thigh.R", "thigh.R")
    # "LeftShoulder" is the clavicle in CMU's names, the upper arm in Xsens MVN's BVH.
    assert rigs["CMU/Vicon"].landmarks["left_clavicle"] == ("LeftShoulder",)
    assert rigs["Xsens MVN"].landmarks["left_shoulder"] == ("LeftShoulder",)
    for rig in RIGS:
        for side in ("left", "right"):
            assert f"{side}_hip" in rig.landmarks and f"{side}_wrist" in rig.landmarks


# -- bad files ---------------------------------------------------------------------------------


def one_line(call) -> str:
    with pytest.raises(KeypointFileError) as info:
        call()
    message = str(info.value)
    assert "\n" not in message and message.strip() == message, message
    return message


@pytest.fixture
def good_text(twin) -> str:
    body, st, _ = twin
    return twin_bvh(st.model.forward(st.q[:3]), body)


def bad(text: str, name: str = "bad.bvh") -> str:
    Path(name).write_text(text)
    return one_line(lambda: read_bvh(name))


def test_bvh_without_hierarchy(here, good_text):
    message = bad(good_text.replace("HIERARCHY", "HIERARCHIES", 1))
    assert message.startswith("bad.bvh is not a BVH file: it does not start with HIERARCHY")
    assert bad("").startswith("bad.bvh is not a BVH file")


def test_bvh_frame_row_with_the_wrong_value_count(here, good_text):
    lines = good_text.splitlines()
    lines[-2] += " 0.5"  # frame 2 of 3
    message = bad("\n".join(lines))
    assert message == (f"bad.bvh: line {len(lines) - 1}: frame 2 has "
                       f"{len(lines[-2].split())} values; the HIERARCHY has "
                       f"{len(lines[-2].split()) - 1} channels")


def test_bvh_missing_the_elbow(here, good_text):
    message = bad(good_text.replace("LeftForeArm", "LeftLowerArm"))
    assert message == ("bad.bvh: no joint for the left elbow (looked for LeftForeArm: the "
                       "Mixamo rig's name for it, whose names the file's fit best; --joint-map "
                       "left_elbow=JOINT names it)")


def test_bvh_channels_count_not_matching_its_names(here, good_text):
    lines = good_text.splitlines()
    at = next(i for i, line in enumerate(lines) if "CHANNELS 3" in line)
    lines[at] = lines[at].replace("CHANNELS 3", "CHANNELS 4")
    message = bad("\n".join(lines))
    assert message.startswith(f"bad.bvh: line {at + 1}: CHANNELS 4 lists 3 channel(s)")


def test_bvh_frames_not_matching_the_rows(here, good_text):
    message = bad(good_text.replace("Frames: 3", "Frames: 5"))
    assert message == "bad.bvh: 'Frames: 5' but the MOTION section has 3 frame rows"


def test_bvh_non_numeric_motion_value(here, good_text):
    lines = good_text.splitlines()
    values = lines[-1].split()
    values[7] = "abc"
    lines[-1] = " ".join(values)
    message = bad("\n".join(lines))
    assert message == f"bad.bvh: line {len(lines)}: frame 3: 'abc' is not a number"


def test_bvh_bad_hierarchy_lines(here, good_text):
    assert "unknown" not in bad(good_text.replace("Zrotation", "Zturn", 1))
    assert "channel 'Zturn' is not known" in bad(good_text.replace("Zrotation", "Zturn", 1))
    assert "OFFSET value 'x' is not a number" in bad(
        good_text.replace("OFFSET 0 0 0", "OFFSET 0 x 0", 1))
    head, tail = good_text.split("MOTION")
    unclosed = head.rstrip().removesuffix("}") + "\nMOTION" + tail
    assert bad(unclosed) == "bad.bvh: the HIERARCHY ends with Hips still open (a '}' is missing)"
    assert bad(good_text.replace("MOTION", "FOO")).startswith("bad.bvh: line ")


def test_bvh_bad_units_and_missing_file(here):
    assert one_line(lambda: read_bvh("none.bvh", units="ft")).startswith(
        "none.bvh: units 'ft'")
    assert one_line(lambda: read_bvh("none.bvh")) == "none.bvh does not exist"
