"""BVH files of the common producers' rigs, read through ``ergohandover score`` without naming
their joints: each rig's names, hierarchy and unit laid on the worker twin's postures (with the
zero-offset neck and clavicle joints real exports have, and a prop far from the body) come back
as the twin's own angles, with the trunk, neck and upper arms measured; ``--joint-map`` reads a
rig of other names, and a bad map is refused in one line with nothing written."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from cli_run import run_cli
from twin_postures import random_twin_postures

from ergohandover.capture.bvh import read_bvh
from ergohandover.capture.rigs import RIGS, recognise
from ergohandover.capture.twin_bvh import joints_bvh, twin_point

TOLERANCE_DEG = 2.0
SIDES = {"left": {"Side": "Left", "S": "L"}, "right": {"Side": "Right", "S": "R"}}
ANGLES = (
    "trunk_flexion", "trunk_side_bend", "trunk_twist", "neck_flexion", "neck_side_bend",
    *(f"{side}_{name}" for side in SIDES for name in (
        "knee_flexion", "upper_arm_flexion", "upper_arm_abduction", "upper_arm_rotation",
        "elbow_flexion", "shoulder_raise", "wrist_flexion", "wrist_deviation", "wrist_twist")),
)
SEEN = ("trunk_flexion", "trunk_side_bend", "trunk_twist", "neck_flexion", "neck_side_bend",
        *(f"{side}_{name}" for side in SIDES for name in (
            "upper_arm_flexion", "upper_arm_abduction", "upper_arm_rotation", "shoulder_raise",
            "elbow_flexion", "knee_flexion")))
"""What every rig measures in every frame (the neck's twist needs a face, which BVH has not)."""
WRISTS = tuple(f"{side}_wrist_{name}" for side in SIDES for name in ("flexion", "deviation"))
"""What a rig with a thumb (or index and little finger) also measures."""

# A rig's skeleton: (name, parent, twin point, twin link whose rotation it takes); {Side}/{S}
# names are one joint per side. Points: placement.POINTS' keys; "thorax" the thorax's own
# joint (the lumbar spine), "clavicle" the clavicle's (on the neck base), "prop" 3 m from the
# hand. A joint on its parent's point has a zero offset.
Node = tuple[str, str | None, str, str]
ARM_LINKS = {"clavicle", "upper_arm", "forearm_pronation_link", "hand"}


def legs(root: str, hip: str, knee: str, ankle: str, toe: str | None = None,
         pelvis: str | None = None) -> list[Node]:
    """Hip, knee, ankle (and toe) joints of both sides; ``pelvis`` a zero-offset joint between
    the root and the hip (CMU's ``LHipJoint``)."""
    out: list[Node] = [(pelvis, root, "pelvis", "pelvis")] if pelvis else []
    above = pelvis or root
    out += [(hip, above, "hip", "thigh"), (knee, hip, "knee", "shank"),
            (ankle, knee, "ankle", "feet")]
    return out + ([(toe, ankle, "toe", "feet")] if toe else [])


def trunk(root: str, spine: list[str], neck: str, head: list[str],
          head_points: tuple[str, ...] = ("head_joint", "head_centre")) -> list[Node]:
    """The spine's joints bottom to top, the last on the neck base; the neck on it (a zero
    offset); the head's joints above the neck (at ``head_points``)."""
    points = [*["thorax", "spine_mid", "spine_high"][:len(spine) - 1], "neck_base"]
    out: list[Node] = []
    parent = root
    for name, point in zip(spine, points, strict=True):
        out.append((name, parent, point, "thorax"))
        parent = name
    out.append((neck, parent, "neck_base", "head"))
    parent = neck
    for name, point in zip(head, head_points, strict=False):
        out.append((name, parent, point, "head"))
        parent = name
    return out


def arms(chest: str, clavicle: str, shoulder: str, elbow: str, wrist: str,
         fingers: tuple[tuple[str, str | None, str], ...] = ()) -> list[Node]:
    """Clavicle (on the chest's top joint, a zero offset), shoulder, elbow, wrist and
    ``fingers`` (name, parent or None for the wrist, point)."""
    out: list[Node] = [(clavicle, chest, "clavicle", "clavicle"),
                       (shoulder, clavicle, "shoulder", "upper_arm"),
                       (elbow, shoulder, "elbow", "forearm_pronation_link"),
                       (wrist, elbow, "wrist", "hand")]
    return out + [(name, parent or wrist, point, "hand") for name, parent, point in fingers]


CMU_FINGERS = (("{Side}FingerBase", None, "wrist"), ("{Side}HandIndex1", "{Side}FingerBase",
                                                    "hand"), ("{S}Thumb", None, "wrist"))
MIXAMO_FINGERS = tuple((f"{{Side}}Hand{f}1", None, p) for f, p in (
    ("Thumb", "thumb"), ("Index", "index"), ("Middle", "hand"), ("Pinky", "pinky")))
NEURON_FINGERS = (("{Side}HandThumb1", None, "thumb"),
                  *((f"{{Side}}InHand{f}", None, "wrist") for f in ("Index", "Middle", "Pinky")),
                  *((f"{{Side}}Hand{f}1", f"{{Side}}InHand{f}", p) for f, p in (
                      ("Index", "index"), ("Middle", "hand"), ("Pinky", "pinky"))))
RIGIFY_FINGERS = tuple((f"DEF-{f}.01.{{S}}", None, p) for f, p in (
    ("thumb", "thumb"), ("f_index", "index"), ("f_middle", "hand"), ("f_pinky", "pinky")))

RIG_FILES: dict[str, tuple[str, list[Node], dict[str, str], str, bool]] = {
    # rig -> (unit, skeleton, End Sites {joint: point}, the joint the prop hangs on, wrists)
    "Xsens MVN": ("cm", [
        ("Hips", None, "pelvis", "pelvis"),
        *trunk("Hips", ["Chest", "Chest2", "Chest3", "Chest4"], "Neck", ["Head"]),
        *arms("Chest4", "{Side}Collar", "{Side}Shoulder", "{Side}Elbow", "{Side}Wrist"),
        *legs("Hips", "{Side}Hip", "{Side}Knee", "{Side}Ankle", "{Side}Toe")],
        {"Head": "head_top", "{Side}Wrist": "hand", "{Side}Toe": "toe"}, "RightWrist", False),
    "Xsens MVN segments": ("cm", [
        ("Pelvis", None, "pelvis", "pelvis"),
        *trunk("Pelvis", ["L5", "L3", "T12", "T8"], "Neck", ["Head"]),
        *arms("T8", "{Side}Shoulder", "{Side}UpperArm", "{Side}ForeArm", "{Side}Hand"),
        *legs("Pelvis", "{Side}UpperLeg", "{Side}LowerLeg", "{Side}Foot", "{Side}Toe")],
        {"Head": "head_top", "{Side}Hand": "hand", "{Side}Toe": "toe"}, "RightHand", False),
    "CMU/Vicon": (str(0.0254 / 0.45), [
        ("Hips", None, "pelvis", "pelvis"),
        *legs("Hips", "{Side}UpLeg", "{Side}Leg", "{Side}Foot", "{Side}ToeBase",
              pelvis="{S}HipJoint"),
        *trunk("Hips", ["LowerBack", "Spine", "Spine1"], "Neck", ["Neck1", "Head"]),
        *arms("Spine1", "{Side}Shoulder", "{Side}Arm", "{Side}ForeArm", "{Side}Hand",
              CMU_FINGERS)],
        {"Head": "head_top", "{Side}ToeBase": "toe", "{Side}HandIndex1": "handtip",
         "{S}Thumb": "thumb"}, "RightHand", True),
    "Mixamo": ("cm", [
        ("Hips", None, "pelvis", "pelvis"),
        *trunk("Hips", ["Spine", "Spine1", "Spine2"], "Neck", ["Head", "HeadTop_End"],
               ("head_joint", "head_top")),
        *arms("Spine2", "{Side}Shoulder", "{Side}Arm", "{Side}ForeArm", "{Side}Hand",
              MIXAMO_FINGERS),
        *legs("Hips", "{Side}UpLeg", "{Side}Leg", "{Side}Foot", "{Side}ToeBase")],
        {"HeadTop_End": "head_top", "{Side}ToeBase": "toe"}, "RightHand", True),
    "Rokoko Studio": ("cm", [
        ("Hips", None, "pelvis", "pelvis"),
        *trunk("Hips", ["Spine1", "Spine2", "Spine3", "Spine4"], "Neck", ["Head"]),
        *arms("Spine4", "{Side}Shoulder", "{Side}Arm", "{Side}ForeArm", "{Side}Hand"),
        *legs("Hips", "{Side}Thigh", "{Side}Shin", "{Side}Foot", "{Side}Toe")],
        {"Head": "head_top", "{Side}Hand": "hand", "{Side}Toe": "toe"}, "RightHand", False),
    "OptiTrack Motive": ("m", [
        ("Hip", None, "pelvis", "pelvis"),
        *trunk("Hip", ["Ab", "Chest"], "Neck", ["Head"]),
        *arms("Chest", "{S}Shoulder", "{S}UArm", "{S}FArm", "{S}Hand"),
        *legs("Hip", "{S}Thigh", "{S}Shin", "{S}Foot", "{S}Toe")],
        {"Head": "head_top", "{S}Hand": "hand", "{S}Toe": "toe"}, "RHand", False),
    "Perception Neuron": ("cm", [
        ("Hips", None, "pelvis", "pelvis"),
        *legs("Hips", "{Side}UpLeg", "{Side}Leg", "{Side}Foot"),
        *trunk("Hips", ["Spine", "Spine1", "Spine2", "Spine3"], "Neck", ["Neck1", "Head"]),
        *arms("Spine3", "{Side}Shoulder", "{Side}Arm", "{Side}ForeArm", "{Side}Hand",
              NEURON_FINGERS)],
        {"Head": "head_top", "{Side}Foot": "toe"}, "RightHand", True),
    "Blender Rigify": ("m", [
        ("DEF-spine", None, "pelvis", "pelvis"),
        *trunk("DEF-spine", ["DEF-spine.001", "DEF-spine.002", "DEF-spine.003"],
               "DEF-spine.004", ["DEF-spine.005", "DEF-spine.006"]),
        *arms("DEF-spine.003", "DEF-shoulder.{S}", "DEF-upper_arm.{S}", "DEF-forearm.{S}",
              "DEF-hand.{S}", RIGIFY_FINGERS),
        *legs("DEF-spine", "DEF-thigh.{S}", "DEF-shin.{S}", "DEF-foot.{S}", "DEF-toe.{S}")],
        {"DEF-spine.006": "head_top", "DEF-toe.{S}": "toe"}, "DEF-hand.R", True),
}


def sided(name: str, side: str) -> str:
    return name.format(**SIDES[side])


def expand(nodes: list[Node], ends: dict[str, str]) -> tuple[list[Node], dict[str, tuple]]:
    """Both sides' joints (left then right, each where its first side's joint is) and End
    Sites, with the sides' names filled in; nodes as (name, parent, point, link, side)."""
    out, done = [], set()
    for name, parent, point, link in nodes:
        for side in SIDES if "{" in name else (None,):
            full = sided(name, side) if side else name
            if full in done:
                continue
            done.add(full)
            up = sided(parent, side) if parent and side else parent
            out.append((full, up, point, link, side))
    sites = {}
    for name, point in ends.items():
        for side in SIDES if "{" in name else (None,):
            sites[sided(name, side) if side else name] = (point, side)
    return out, sites


def skeleton(body, nodes: list[Node], ends: dict[str, str], prop_on: str):
    """The twin joints and End Sites of a rig (joints_bvh's input), with two props: a tool in
    the hand ``prop_on`` (a joint on the wrist, its End Site 0.4 m beyond the hand) and one
    parked 4 m beside the body (a joint on the root, its End Site 4 m to the side), which
    would make the body 4 m across if it counted as the body."""
    joints, sites = expand(nodes, ends)
    out = []
    for name, parent, point, link, side in joints:
        out.append((name, parent, *where(body, point, side),
                    f"{side}_{link}" if link in ARM_LINKS else link))
    prop_side = next(side for name, *_, side in joints if name == prop_on)
    out.append(("Prop1", prop_on, *where(body, "wrist", prop_side), f"{prop_side}_hand"))
    out.append(("Prop2", out[0][0], *where(body, "pelvis", None), "pelvis"))
    sites = {name: where(body, point, side) for name, (point, side) in sites.items()}
    sites["Prop1"] = (f"{prop_side}_hand", (0.0, 0.0, -0.4))
    sites["Prop2"] = ("pelvis", (0.0, 4.0, 0.0))
    return out, sites


def where(body, point: str, side: str | None) -> tuple[str, tuple]:
    if point == "thorax":
        return "thorax", (0.0, 0.0, 0.0)
    if point == "clavicle":
        return f"{side}_clavicle", (0.0, 0.0, 0.0)
    return twin_point(body, point, side)


@pytest.fixture(scope="module")
def postures():
    """Twin postures with both elbows bent (the upper arm's rotation is seen): body, forward
    kinematics, the twin's own columns."""
    body, st, truth = random_twin_postures(40, 5)
    keep = np.flatnonzero((truth["left_elbow_flexion"] > 20)
                          & (truth["right_elbow_flexion"] > 20))[:8]
    assert len(keep) >= 5
    return body, st.model.forward(st.q[keep]), {k: np.asarray(v)[keep] for k, v in
                                                  truth.items()}


def write_rig(tmp_path: Path, rig: str, postures, rename=None) -> tuple[Path, str]:
    """The postures as a BVH file of ``rig`` (joints renamed by ``rename``); its unit."""
    body, st, _ = postures
    unit, nodes, ends, prop_on, _ = RIG_FILES[rig]
    joints, sites = skeleton(body, nodes, ends, prop_on)
    text = joints_bvh(st, joints, sites, units=unit)
    if rename:
        for old, new in rename.items():
            text = text.replace(f"JOINT {old}\n", f"JOINT {new}\n").replace(
                f"ROOT {old}\n", f"ROOT {new}\n")
    path = tmp_path / f"{rig.replace('/', '_').replace(' ', '_')}.bvh"
    path.write_text(text)
    return path, unit


def scored(path: Path, unit: str | None, *flags: str) -> tuple[pd.DataFrame, str]:
    """The file scored through the command (``unit`` None: no --units, the unit told from the
    legs); its table and what it said."""
    out = path.with_suffix(".csv")
    given = ["--units", unit] if unit is not None else []
    done = run_cli("score", "--keypoints", str(path), "--format", "bvh", *given,
                   "--output", str(out), *flags)
    assert done.returncode == 0, done.stderr
    return pd.read_csv(out), done.stderr


def test_every_rig_is_in_the_table():
    assert sorted(RIG_FILES) == sorted(rig.name for rig in RIGS)


@pytest.mark.parametrize("rig", list(RIG_FILES))
def test_each_rig_read_without_flags_gives_the_postures_angles(rig, tmp_path, postures):
    _, _, truth = postures
    path, unit = write_rig(tmp_path, rig, postures)
    table, said = scored(path, None)  # no flags: the rig and its unit are told from the file
    told = {"m": "m", "cm": "cm", str(0.0254 / 0.45): "CMU's 1/0.45 inch"}[unit]
    assert f"(bvh: {rig} rig, up y, units {told}, told from the legs)" in said, said
    with_wrists = RIG_FILES[rig][4]
    for column in (*SEEN, *(WRISTS if with_wrists else ())):
        assert table[column].notna().all(), f"{rig}: {column} unseen"
    for column in ANGLES:
        got = table[column].to_numpy(dtype=float)
        seen = np.isfinite(got)
        error = np.abs((got[seen] - truth[column][seen] + 180.0) % 360.0 - 180.0)
        assert error.max(initial=0.0) < TOLERANCE_DEG, (rig, column, error.max())
    for flag in ("hands_above_neck", "left_arm_across_midline", "right_arm_across_midline"):
        got = table[flag].to_numpy(dtype=float)
        seen = np.isfinite(got)
        np.testing.assert_array_equal(got[seen], truth[flag][seen], err_msg=f"{rig}: {flag}")


def test_the_names_decide_what_left_shoulder_is(tmp_path, postures):
    """CMU's LeftShoulder is the clavicle, Xsens MVN's the upper arm; and CMU's zero-offset
    Neck keeps the neck base while the spine moves down to Spine, its zero-offset finger base
    and thumb give way to the index and the thumb's tip."""
    marks = {}
    for rig in ("CMU/Vicon", "Xsens MVN"):
        path, unit = write_rig(tmp_path, rig, postures)
        kp = read_bvh(path, unit)
        marks[rig] = {m: j[0] for m, j in kp.fmt.landmarks.items()}
        assert "Prop1_End" not in kp.fmt.body and "Prop2_End" not in kp.fmt.body
        assert "Hips" in kp.fmt.body and "Head_End" in kp.fmt.body
    assert marks["CMU/Vicon"]["left_clavicle"] == "LeftShoulder"
    assert marks["Xsens MVN"]["left_shoulder"] == "LeftShoulder"
    assert marks["Xsens MVN"]["left_clavicle"] == "LeftCollar"
    cmu = marks["CMU/Vicon"]
    assert (cmu["neck_base"], cmu["spine"]) == ("Neck", "Spine")
    assert (cmu["right_hand"], cmu["right_thumb"]) == ("RightHandIndex1", "RThumb_End")


def test_a_zero_offset_neck_read_as_before_leaves_the_trunk_unseen(tmp_path, postures):
    """The cause the resolution removes: CMU's Neck on Spine1, both taken as they are named,
    make the trunk a point (what the reader did before rigs were recognised)."""
    from ergohandover.capture.angles import measure
    from ergohandover.capture.formats import KeypointFormat

    path, unit = write_rig(tmp_path, "CMU/Vicon", postures)
    kp = read_bvh(path, unit)
    naive = dict(kp.fmt.landmarks) | {"spine": ("Spine1",)}
    got = measure(kp.points, KeypointFormat("bvh", "", kp.fmt.joints, "y", naive), "y")
    assert np.isnan(got["trunk_flexion"]).all() and np.isnan(got["left_upper_arm_flexion"]).all()
    assert np.isfinite(measure(kp.points, kp.fmt, "y")["trunk_flexion"]).all()


def test_recognition_counts_the_names_that_fit():
    rig, fit = recognise(["Hips", "LeftHip", "LeftKnee", "LeftCollar", "LeftShoulder",
                          "Chest4", "Neck"])
    assert (rig.name, fit) == ("Xsens MVN", 7)
    rig, fit = recognise(["Pelvis", "T8", "LeftShoulder", "LeftUpperArm", "Neck"])
    assert (rig.name, fit) == ("Xsens MVN segments", 5)
    assert recognise(["Hips", "LeftShoulder", "Spine1", "Neck1", "LHipJoint"])[0].name == \
        "CMU/Vicon"
    assert recognise(["foo", "bar"])[1] == 0


def test_a_file_of_unknown_names_says_so(tmp_path, postures):
    path, unit = write_rig(tmp_path, "CMU/Vicon", postures, rename={
        name: f"j{k}" for k, name in enumerate(("Hips", "LHipJoint", "RHipJoint"))})
    text = path.read_text()
    for k, name in enumerate(sorted(set(re.findall(r"JOINT (\S+)\n", text)), reverse=True)):
        text = text.replace(f"JOINT {name}\n", f"JOINT x{k}\n")
    path.write_text(text)
    message = refused(tmp_path, "--keypoints", str(path), "--format", "bvh", "--units", unit)
    assert message == (f"{path}: no joint for the left hip: the file's joint names fit none of "
                       "the rigs known (Xsens MVN, Xsens MVN segments, CMU/Vicon, Mixamo, "
                       "Rokoko Studio, OptiTrack Motive, Perception Neuron, Blender Rigify); "
                       "--joint-map left_hip=JOINT,... names its landmarks")


# --joint-map -----------------------------------------------------------------------------------

BIPED = {"Hips": "Bip01_Pelvis", "LowerBack": "Bip01_Spine", "Spine": "Bip01_Spine1",
         "Spine1": "Bip01_Spine2", "Neck": "Bip01_Neck", "Neck1": "Bip01_Neck1",
         "Head": "Bip01_Head", **{f"{S}{old}": f"Bip01_{S[0]}_{new}" for S in ("Left", "Right")
                                  for old, new in (
             ("UpLeg", "Thigh"), ("Leg", "Calf"), ("Foot", "Foot"), ("ToeBase", "Toe0"),
             ("Shoulder", "Clavicle"), ("Arm", "UpperArm"), ("ForeArm", "Forearm"),
             ("Hand", "Hand"), ("FingerBase", "Finger0"), ("HandIndex1", "Finger1"))}}
"""CMU's joints renamed as 3ds Max's Biped names them (a rig the table does not know)."""
BIPED_MAP = ",".join([
    "spine=Bip01_Spine1", "neck_base=Bip01_Neck", "head_top=Bip01_Head_End",
    *(f"{side}_{mark}=Bip01_{side[0].upper()}_{joint}" for side in SIDES for mark, joint in (
        ("hip", "Thigh"), ("knee", "Calf"), ("ankle", "Foot"), ("clavicle", "Clavicle"),
        ("shoulder", "UpperArm"), ("elbow", "Forearm"), ("wrist", "Hand"),
        ("hand", "Finger1")))])


def refused(tmp_path: Path, *argv: str) -> str:
    """``score`` ARGV: exit 2, one line on stderr, nothing written under tmp_path."""
    before = sorted(tmp_path.rglob("*"))
    done = run_cli("score", *argv, "--output", str(tmp_path / "out" / "scores.csv"))
    assert done.returncode == 2, done.stderr
    assert done.stdout == "" and done.stderr.count("\n") == 1, done.stderr
    assert sorted(tmp_path.rglob("*")) == before, "a refused command wrote something"
    return done.stderr.removeprefix("ergohandover score: error: ").rstrip("\n")


def test_an_unknown_rig_is_read_with_a_joint_map(tmp_path, postures):
    _, _, truth = postures
    path, unit = write_rig(tmp_path, "CMU/Vicon", postures, rename=BIPED)
    flags = ["--keypoints", str(path), "--format", "bvh", "--units", unit]
    message = refused(tmp_path, *flags)
    assert message.startswith(f"{path}: no joint for the left hip (looked for ") and \
        "--joint-map left_hip=JOINT names it" in message, message
    mapfile = tmp_path / "biped.map"
    mapfile.write_text("# 3ds Max Biped\n" + BIPED_MAP.replace(",", "\n") + "\n")
    for given in (BIPED_MAP, str(mapfile)):
        table, said = scored(path, unit, "--joint-map", given)
        assert "by --joint-map, the others by the CMU/Vicon rig, up y, --units " in said, said
        for column in ("trunk_flexion", "neck_flexion", "left_upper_arm_flexion",
                       "right_shoulder_raise", "right_upper_arm_rotation", "left_knee_flexion"):
            got = table[column].to_numpy(dtype=float)
            assert np.isfinite(got).all(), column
            assert np.abs(got - truth[column]).max() < TOLERANCE_DEG, column


def test_a_joint_map_overrides_one_landmark_of_a_known_rig(tmp_path, postures):
    _, _, truth = postures
    path, unit = write_rig(tmp_path, "CMU/Vicon", postures)
    # The spine on Spine1, as mapped: the rig's neck base gives way to Neck1, so the "trunk"
    # is the neck's bone and leans as the head does, not as the twin's trunk.
    table, said = scored(path, unit, "--joint-map", "spine=Spine1")
    assert "(bvh: 1 landmark(s) by --joint-map, the others by the CMU/Vicon rig" in said, said
    got = table["trunk_flexion"].to_numpy(dtype=float)
    assert np.isfinite(got).all() and np.abs(got - truth["trunk_flexion"]).max() > 10.0


@pytest.mark.parametrize("value, says", [
    ("left_hipp=Bip01_L_Thigh", "--joint-map left_hipp=Bip01_L_Thigh: 'left_hipp' is not a "
     "landmark (did you mean left_hip? use left_hip, right_hip,"),
    ("left_hip", "--joint-map left_hip: no such file, and not LANDMARK=JOINT,..."),
    ("left_hip=", "--joint-map left_hip=: 'left_hip=' is not LANDMARK=JOINT"),
    ("left_hip=A,left_hip=B", "--joint-map left_hip=A,left_hip=B: left_hip is mapped twice"),
    ("left_hip=Bip01_L_Thig", "--joint-map left_hip=Bip01_L_Thig: {file} has no joint "
     "'Bip01_L_Thig' for left_hip (did you mean Bip01_L_Thigh? its joints: Bip01_Pelvis, "),
])
def test_a_bad_joint_map_is_refused_in_one_line(value, says, tmp_path, postures):
    path, unit = write_rig(tmp_path, "CMU/Vicon", postures, rename=BIPED)
    message = refused(tmp_path, "--keypoints", str(path), "--format", "bvh", "--units", unit,
                      "--joint-map", value)
    assert message.startswith(says.format(file=path)), message


def test_a_joint_map_needs_a_bvh_file(tmp_path):
    keypoints = Path(__file__).resolve().parents[1] / "examples" / "keypoints" / "h36m17.csv"
    message = refused(tmp_path, "--keypoints", str(keypoints), "--format", "h36m17",
                      "--joint-map", "spine=spine")
    assert message == ("--joint-map cannot be used with --format h36m17 (only with bvh: the "
                       "other formats' joints are fixed)")


def test_rotations_in_radians_are_refused_and_read_with_radians(tmp_path, postures):
    from ergohandover.capture.bvh import _parse_hierarchy

    path = write_rig(tmp_path, "CMU/Vicon", postures)[0]
    lines = path.read_text().splitlines()
    nodes, _ = _parse_hierarchy(lines, str(path))
    turns = np.array([c.endswith("rotation") for node in nodes for c in node.channels])
    first = next(i for i, line in enumerate(lines) if line.startswith("Frame Time")) + 1
    for i in range(first, len(lines)):
        values = np.array(lines[i].split(), dtype=float)
        values[turns] = np.radians(values[turns])
        lines[i] = " ".join(f"{v:.9g}" for v in values)
    radians = tmp_path / "radians.bvh"
    radians.write_text("\n".join(lines) + "\n")
    out = tmp_path / "r.csv"
    done = run_cli("score", "--keypoints", str(radians), "--format", "bvh", "--output",
                   str(out))
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1
    assert "these look like radians, and BVH rotations are degrees; give --radians" in \
        done.stderr
    assert not out.exists()
    table, _ = scored(radians, None, "--radians")
    want, _ = scored(path, None)
    for column in SEEN:
        np.testing.assert_allclose(table[column], want[column], atol=1e-3, err_msg=column)


# Every joint with position channels (Perception Neuron "with displacement") --------------------


def every_joint_moves(text: str) -> str:
    """A BVH text whose joints below the root have rotation channels only, rewritten as
    Perception Neuron writes "with displacement": six channels for every joint, the position
    channels holding the joint's local translation (its OFFSET) in every frame."""
    lines, offsets, roots, last = text.splitlines(), [], [], None
    for i, line in enumerate(lines):
        words = line.split()
        if words[:1] == ["OFFSET"]:
            last = words[1:]
        elif words[:1] == ["CHANNELS"]:
            roots.append(words[1] == "6")
            offsets.append(None if words[1] == "6" else last)
            if words[1] == "3":
                lines[i] = line.replace("CHANNELS 3", "CHANNELS 6 Xposition Yposition Zposition")
    first = next(i for i, line in enumerate(lines) if line.startswith("Frame Time")) + 1
    for i in range(first, len(lines)):
        values, row = lines[i].split(), []
        for offset in offsets:
            take = 6 if offset is None else 3
            row += (offset or []) + values[:take]
            values = values[take:]
        lines[i] = " ".join(row)
    return "\n".join(lines) + "\n"


def test_position_channels_on_every_joint_keep_the_offsets_bones(tmp_path, postures):
    """A Perception Neuron file whose every joint has six channels: its bones are its OFFSETs'
    (not twice them) and the postures come back within the tolerance."""
    _, _, truth = postures
    path, unit = write_rig(tmp_path, "Perception Neuron", postures)
    three = read_bvh(path, unit)
    path.write_text(every_joint_moves(path.read_text()))
    assert path.read_text().count("CHANNELS 6") == path.read_text().count("CHANNELS")
    six = read_bvh(path, unit)
    np.testing.assert_allclose(six.points, three.points, atol=1e-6)
    table, said = scored(path, None)
    assert "(bvh: Perception Neuron rig, up y, units cm, told from the legs)" in said, said
    for column in ANGLES:
        got = table[column].to_numpy(dtype=float)
        seen = np.isfinite(got)
        assert seen.any() or column not in SEEN, column
        error = np.abs((got[seen] - truth[column][seen] + 180.0) % 360.0 - 180.0)
        assert error.max(initial=0.0) < TOLERANCE_DEG, (column, error.max())
