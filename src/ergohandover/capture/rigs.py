"""BVH rigs as data: the joint names each common BVH producer writes, which joint is each
landmark, and the rig a file's whole set of names fits best.

A joint's name alone does not say what it is: ``LeftShoulder`` is the clavicle in CMU's, Mixamo's
and Perception Neuron's skeletons but the upper arm in Xsens MVN's BVH export, so a file's rig
is recognised from all its names at once (:func:`recognise`), and only then are its joints read
as landmarks. A BVH joint's position is where it turns, so each landmark is the joint that turns
*at* it (the hip is the thigh's joint, the shoulder the upper arm's, the clavicle's medial end
the clavicle's); ``<joint>_End`` is the End Site of a joint (the reader's naming).

Where each naming comes from (read for the names; none of their code is used):

- Xsens MVN, BVH names (``Hips, Chest, Chest2, Chest3, Chest4, Neck, Head, LeftCollar,
  LeftShoulder, LeftElbow, LeftWrist, LeftHip, LeftKnee, LeftAnkle, LeftToe``): MVN's own BVH
  exports as they circulate in public motion sets (centimetres or metres, ``Yrotation Xrotation
  Zrotation``; the collar on ``Chest4``, the hand an End Site of the wrist);
- Xsens MVN, segment names (``Pelvis, L5, L3, T12, T8, Neck, Head, LeftShoulder`` = the
  clavicle, ``LeftUpperArm, LeftForeArm, LeftHand, LeftUpperLeg, LeftLowerLeg, LeftFoot,
  LeftToe``): the segment list of the MVN user manual's biomechanical model;
- CMU/Vicon (``Hips, LHipJoint, LeftUpLeg, LeftLeg, LeftFoot, LeftToeBase, LowerBack, Spine,
  Spine1, Neck, Neck1, Head, LeftShoulder, LeftArm, LeftForeArm, LeftHand, LeftFingerBase,
  LeftHandIndex1, LThumb``): the CMU motion capture database's BVH conversion, whose ``Neck``,
  ``LeftShoulder``, ``LeftFingerBase`` and ``LThumb`` have zero offsets (they sit on ``Spine1``
  and ``LeftHand``), unit 1/0.45 inch;
- Mixamo (``mixamorig:`` stripped: ``Hips, Spine, Spine1, Spine2, Neck, Head, HeadTop_End,
  LeftShoulder, LeftArm, LeftForeArm, LeftHand, LeftHandThumb1..4, LeftHandIndex1..4, ...,
  LeftUpLeg, LeftLeg, LeftFoot, LeftToeBase, LeftToe_End``): Mixamo's character skeleton;
- Rokoko Studio (``Hips, Spine1..Spine4, Neck, Head, LeftShoulder, LeftArm, LeftForeArm,
  LeftHand, LeftThigh, LeftShin, LeftFoot, LeftToe``): Studio's BVH export as retargeting
  configurations for Rokoko files list it;
- OptiTrack Motive (``Hip, Ab, Chest, Neck, Head, LShoulder, LUArm, LFArm, LHand, LThigh,
  LShin, LFoot, LToe``): Motive's BVH export with its own segment names (with "MotionBuilder
  names" it writes Mixamo-like ones);
- Perception Neuron, Axis Neuron/Axis Studio (``Hips, Spine, Spine1, Spine2, Spine3, Neck,
  Neck1, Head, LeftShoulder, LeftArm, LeftForeArm, LeftHand, LeftHandThumb1..3,
  LeftInHandIndex, LeftHandIndex1..3, LeftInHandMiddle, ..., LeftUpLeg, LeftLeg, LeftFoot``):
  Axis Neuron's BVH header;
- Blender Rigify (deform bones ``DEF-spine``, ``DEF-spine.001``..``.006``, ``DEF-shoulder.L``,
  ``DEF-upper_arm.L``, ``DEF-forearm.L``, ``DEF-hand.L``, ``DEF-thigh.L``, ``DEF-shin.L``,
  ``DEF-foot.L``, ``DEF-toe.L``, fingers ``DEF-thumb.01.L``, ``DEF-f_index.01.L``, ...; and
  the metarig's same names without ``DEF-``): Rigify's human metarig, as Blender's BVH exporter
  writes bones (a joint at each bone's head).

Zero-length segments: a joint that sits on another (a zero offset) is where that one is, so a
landmark read from it may coincide with the landmark it is measured against (CMU's ``Neck`` on
``Spine1`` would make the trunk a point). :func:`resolve` takes each landmark from the first of
its joints that does not coincide with the landmarks it is measured against
(:data:`PARTNERS`), in :data:`ORDER`: the neck base keeps CMU's ``Neck`` and the spine moves to
``Spine``; the hand moves from ``LeftFingerBase`` (on the wrist) to ``LeftHandIndex1``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .formats import LANDMARKS, SIDES

SIDE_WORDS = {"left": {"Side": "Left", "S": "L"}, "right": {"Side": "Right", "S": "R"}}
"""How each naming spells a side: ``{Side}UpLeg``, ``{S}Thigh``, ``DEF-thigh.{S}``."""
MIDLINE = ("spine", "neck_base", "head_top")


@dataclass(frozen=True)
class Rig:
    """One producer's BVH naming.

    Attributes:
        name: what the summary calls it.
        landmarks: landmark -> the joints that may be it, in order of preference.
        names: every joint name the rig is known to write (landmarks' and others'), for
            :func:`recognise`.
    """

    name: str
    landmarks: dict[str, tuple[str, ...]]
    names: frozenset[str]


def _expand(pattern: str) -> list[str]:
    """``{Side}``/``{S}`` patterns -> both sides' names (a midline name once)."""
    if "{" not in pattern:
        return [pattern]
    return [pattern.format(**SIDE_WORDS[side]) for side in SIDES]


def _rig(name: str, others: str = "", **parts: str) -> Rig:
    """A rig from ``part="Joint|Other joint"`` patterns (sided parts: ``hip="{Side}UpLeg"``)
    and the ``others`` it writes (space-separated patterns)."""
    landmarks = {}
    for part, patterns in parts.items():
        options = patterns.split("|")
        if part in MIDLINE:
            landmarks[part] = tuple(options)
            continue
        for side in SIDES:
            landmarks[f"{side}_{part}"] = tuple(p.format(**SIDE_WORDS[side]) for p in options)
    unknown = set(landmarks) - set(LANDMARKS)
    if unknown:
        raise ValueError(f"rig {name}: {sorted(unknown)} are not landmarks")
    names = {n for options in landmarks.values() for n in options}
    names |= {n for pattern in others.split() for n in _expand(pattern)}
    return Rig(name, {m: landmarks[m] for m in LANDMARKS if m in landmarks}, frozenset(names))


RIGS: tuple[Rig, ...] = (
    _rig("Xsens MVN", hip="{Side}Hip", knee="{Side}Knee", ankle="{Side}Ankle",
         spine="Chest3|Chest2|Chest4|Chest", neck_base="Neck", head_top="Head_End",
         clavicle="{Side}Collar", shoulder="{Side}Shoulder", elbow="{Side}Elbow",
         wrist="{Side}Wrist", hand="{Side}Wrist_End",
         others="Hips Head {Side}Toe {Side}Toe_End"),
    _rig("Xsens MVN segments", hip="{Side}UpperLeg", knee="{Side}LowerLeg",
         ankle="{Side}Foot", spine="T12|L3|T8|L5", neck_base="Neck", head_top="Head_End",
         clavicle="{Side}Shoulder", shoulder="{Side}UpperArm", elbow="{Side}ForeArm",
         wrist="{Side}Hand", hand="{Side}Hand_End",
         others="Pelvis Head {Side}Toe {Side}Toe_End"),
    _rig("CMU/Vicon", hip="{Side}UpLeg", knee="{Side}Leg", ankle="{Side}Foot",
         spine="Spine1|Spine", neck_base="Neck|Neck1", head_top="Head_End",
         clavicle="{Side}Shoulder", shoulder="{Side}Arm", elbow="{Side}ForeArm",
         wrist="{Side}Hand", hand="{Side}FingerBase|{Side}HandIndex1|{Side}HandIndex1_End",
         thumb="{S}Thumb|{S}Thumb_End",
         others="Hips {S}HipJoint LowerBack Head {Side}ToeBase {Side}ToeBase_End"),
    _rig("Mixamo", hip="{Side}UpLeg", knee="{Side}Leg", ankle="{Side}Foot",
         spine="Spine1|Spine|Spine2", neck_base="Neck", head_top="HeadTop_End|Head_End",
         clavicle="{Side}Shoulder", shoulder="{Side}Arm", elbow="{Side}ForeArm",
         wrist="{Side}Hand", hand="{Side}HandMiddle1", thumb="{Side}HandThumb1",
         index="{Side}HandIndex1", pinky="{Side}HandPinky1",
         others="Hips Head {Side}ToeBase {Side}Toe_End {Side}HandThumb2 {Side}HandThumb3 "
         "{Side}HandThumb4 {Side}HandIndex2 {Side}HandIndex3 {Side}HandIndex4 "
         "{Side}HandMiddle2 {Side}HandMiddle3 {Side}HandMiddle4 {Side}HandRing1 "
         "{Side}HandRing2 {Side}HandRing3 {Side}HandRing4 {Side}HandPinky2 {Side}HandPinky3 "
         "{Side}HandPinky4"),
    _rig("Rokoko Studio", hip="{Side}Thigh", knee="{Side}Shin", ankle="{Side}Foot",
         spine="Spine2|Spine1|Spine3", neck_base="Neck", head_top="Head_End",
         clavicle="{Side}Shoulder", shoulder="{Side}Arm", elbow="{Side}ForeArm",
         wrist="{Side}Hand", hand="{Side}Hand_End",
         others="Hips Spine4 Head {Side}Toe {Side}Toe_End"),
    _rig("OptiTrack Motive", hip="{S}Thigh", knee="{S}Shin", ankle="{S}Foot",
         spine="Chest|Ab", neck_base="Neck", head_top="Head_End", clavicle="{S}Shoulder",
         shoulder="{S}UArm", elbow="{S}FArm", wrist="{S}Hand", hand="{S}Hand_End",
         others="Hip Ab Head {S}Toe {S}Toe_End"),
    _rig("Perception Neuron", hip="{Side}UpLeg", knee="{Side}Leg", ankle="{Side}Foot",
         spine="Spine1|Spine2|Spine", neck_base="Neck", head_top="Head_End",
         clavicle="{Side}Shoulder", shoulder="{Side}Arm", elbow="{Side}ForeArm",
         wrist="{Side}Hand", hand="{Side}HandMiddle1", thumb="{Side}HandThumb1",
         index="{Side}HandIndex1", pinky="{Side}HandPinky1",
         others="Hips Spine3 Neck1 Head {Side}HandThumb2 {Side}HandThumb3 {Side}InHandIndex "
         "{Side}HandIndex2 {Side}HandIndex3 {Side}InHandMiddle {Side}HandMiddle2 "
         "{Side}HandMiddle3 {Side}InHandRing {Side}HandRing1 {Side}HandRing2 {Side}HandRing3 "
         "{Side}InHandPinky {Side}HandPinky2 {Side}HandPinky3"),
    _rig("Blender Rigify", hip="DEF-thigh.{S}|thigh.{S}", knee="DEF-shin.{S}|shin.{S}",
         ankle="DEF-foot.{S}|foot.{S}",
         spine="DEF-spine.002|spine.002|DEF-spine.003|spine.003|DEF-spine.001|spine.001",
         neck_base="DEF-spine.004|spine.004", head_top="DEF-spine.006_End|spine.006_End",
         clavicle="DEF-shoulder.{S}|shoulder.{S}", shoulder="DEF-upper_arm.{S}|upper_arm.{S}",
         elbow="DEF-forearm.{S}|forearm.{S}", wrist="DEF-hand.{S}|hand.{S}",
         hand="DEF-f_middle.01.{S}|f_middle.01.{S}|DEF-hand.{S}_End|hand.{S}_End",
         thumb="DEF-thumb.01.{S}|thumb.01.{S}", index="DEF-f_index.01.{S}|f_index.01.{S}",
         pinky="DEF-f_pinky.01.{S}|f_pinky.01.{S}",
         others="DEF-spine spine DEF-spine.001 spine.001 DEF-spine.005 spine.005 "
         "DEF-spine.006 spine.006 DEF-pelvis.{S} pelvis.{S} DEF-breast.{S} breast.{S} "
         "DEF-toe.{S} toe.{S} DEF-thigh.{S}.001 DEF-shin.{S}.001 DEF-upper_arm.{S}.001 "
         "DEF-forearm.{S}.001 heel.02.{S} palm.01.{S} palm.02.{S} palm.03.{S} palm.04.{S}"),
)
"""The rigs :func:`recognise` knows (the module's text says where each naming comes from); of
equally fitting rigs the first listed is taken."""

PARTNERS: dict[str, tuple[str, ...]] = {
    "head_top": ("neck_base",), "neck_base": ("head_top", "spine"), "spine": ("neck_base",),
    **{f"{s}_{part}": tuple(f"{s}_{p}" for p in partners) for s in SIDES
       for part, partners in (("clavicle", ("shoulder",)), ("hand", ("wrist",)),
                              ("thumb", ("hand", "wrist")), ("index", ("pinky",)),
                              ("pinky", ("index",)))},
}
"""Landmark -> the landmarks it is measured against (a segment or axis of the angles), which it
must not coincide with."""
ORDER = ("head_top", "neck_base", "spine",
         *(f"{s}_{part}" for part in ("clavicle", "hand", "thumb", "index", "pinky")
           for s in SIDES))
"""The order :func:`resolve` chooses the landmarks with PARTNERS in (the others first): the neck
base before the spine, so that a neck joint on the last spine joint keeps the neck base."""
COINCIDE = 1e-3
"""Two joints coincide where they are never further apart than this share of the body's
extent (1.7 mm on a 1.7 m body): a zero offset, or one no direction can be read from."""


def recognise(names: Sequence[str]) -> tuple[Rig, int]:
    """The rig whose names fit ``names`` best (the most of them), and how many fit."""
    present = set(names)
    fits = [len(rig.names & present) for rig in RIGS]
    best = int(np.argmax(fits))
    return RIGS[best], fits[best]


def coincide(points: np.ndarray, a: int, b: int, within: float) -> bool:
    """Whether points ``a`` and ``b`` of (N, J, 3) ``points`` are never further apart than
    ``within``."""
    apart = np.linalg.norm(points[:, a] - points[:, b], axis=-1)
    return bool(np.nanmax(apart, initial=0.0) <= within)


def resolve(rig: Rig, names: Sequence[str], points: np.ndarray | None = None,
            given: Mapping[str, str] | None = None) -> dict[str, str]:
    """Landmark -> joint for a file's joints.

    Args:
        rig: the file's rig.
        names: the file's joints and End Sites.
        points: their (N, J, 3) positions (without, no joint is checked for coinciding).
        given: landmarks the user named (``--joint-map``): taken as given.

    Returns:
        Each landmark the rig (or ``given``) gives: the landmarks without PARTNERS the first of
        their joints the file has; those with, in :data:`ORDER`, the first that does not
        coincide with an already chosen partner (none: the landmark is absent and the angles
        fall back, e.g. a clavicle to the neck base). An index without a pinky is dropped.
    """
    index = {n: i for i, n in enumerate(names)}
    chosen = dict(given or {})
    within = COINCIDE * float(np.nanmax(np.ptp(points, axis=1), initial=0.0)) \
        if points is not None and points.size else 0.0
    for landmark in (*[m for m in rig.landmarks if m not in PARTNERS], *ORDER):
        if landmark in chosen or landmark not in rig.landmarks:
            continue
        for joint in rig.landmarks[landmark]:
            if joint not in index:
                continue
            partners = [chosen[p] for p in PARTNERS.get(landmark, ()) if p in chosen]
            if points is not None and any(coincide(points, index[joint], index[p], within)
                                          for p in partners):
                continue
            chosen[landmark] = joint
            break
    for side in SIDES:
        # The hand's across axis is index-to-pinky only where both are given.
        if f"{side}_index" in chosen and f"{side}_pinky" not in chosen:
            del chosen[f"{side}_index"]
    return {m: chosen[m] for m in LANDMARKS if m in chosen}


def parse_joint_map(text: str) -> dict[str, str]:
    """``landmark=JOINT`` entries (separated by commas or new lines; ``#`` starts a comment)
    -> {landmark: joint}; a ValueError saying what is wrong (one line) otherwise."""
    out: dict[str, str] = {}
    entries = [e.strip() for line in text.splitlines() for e in line.split("#")[0].split(",")]
    for entry in filter(None, entries):
        landmark, sep, joint = (s.strip() for s in entry.partition("="))
        if not sep or not landmark or not joint or len(joint.split()) != 1:
            raise ValueError(f"{entry!r} is not LANDMARK=JOINT (a landmark, '=', one joint "
                             "name of the file)")
        if landmark not in LANDMARKS:
            import difflib

            close = difflib.get_close_matches(landmark, LANDMARKS, n=1)
            hint = f"did you mean {close[0]}? " if close else ""
            raise ValueError(f"{landmark!r} is not a landmark ({hint}use "
                             f"{', '.join(LANDMARKS)})")
        if landmark in out:
            raise ValueError(f"{landmark} is mapped twice ({out[landmark]} and {joint})")
        out[landmark] = joint.split(":")[-1]  # mixamorig:LeftArm -> LeftArm, as the reader
    if not out:
        raise ValueError("no LANDMARK=JOINT entry")
    return out
