"""The worker twin's postures as a BVH file in CMU's joint names: the twin's own motion as a
motion capture system would export it, for the round trips that check the BVH reader and for
the example files.

Each BVH joint sits at a point of the twin (its joint centres, placed as
:data:`~ergohandover.capture.placement.POINTS` places them) and turns with one of its links; at
q = 0 every twin link frame is aligned with the world, so the rest pose's offsets are
differences of rest positions and each joint's local rotation is ``R_parent_link^T @ R_link``.
The twin's legs share one link per segment (both thighs turn together), so each leg's joints are
the points ±hip_width/2 along that link's y.
"""

from __future__ import annotations

import numpy as np

from ..twin.anthropometry import BodySpec
from ..twin.kinematics import KinematicState
from .bvh_write import bvh_text, zxy_angles
from .placement import ARM_LINKS, POINTS, to_axes
from .readers import unit_scale

SIDE_NAMES = {"left": "Left", "right": "Right"}

TwinJoint = tuple[str, str | None, str, tuple[float, float, float], str]
"""(BVH name, BVH parent, twin link of its point, the point's offset in that link [m], twin
link whose rotation it takes)."""


def twin_point(body: BodySpec, key: str, side: str | None = None
               ) -> tuple[str, tuple[float, float, float]]:
    """(twin link, offset in it [m]) of point ``key`` of :data:`~.placement.POINTS` on
    ``side`` (``left``, ``right``, or None on the mid-line)."""
    link, offset = POINTS[key]
    if link in ARM_LINKS:
        link = f"{side}_{link}"
    return link, tuple(offset(body.segments(), {"left": 1.0, "right": -1.0, None: 0.0}[side]))


def twin_joints(body: BodySpec) -> tuple[list[TwinJoint], dict[str, tuple[str, tuple]]]:
    """The BVH joints of the twin in file order, and the End Sites (joint -> link, offset)."""
    zero = (0.0, 0.0, 0.0)

    def point(key: str, side: str | None = None) -> tuple[str, tuple[float, float, float]]:
        return twin_point(body, key, side)

    joints: list[TwinJoint] = [("Hips", None, "pelvis", zero, "pelvis")]
    ends: dict[str, tuple[str, tuple]] = {}
    for side, S in SIDE_NAMES.items():
        joints += [(f"{S}UpLeg", "Hips", *point("hip", side), "thigh"),
                   (f"{S}Leg", f"{S}UpLeg", *point("knee", side), "shank"),
                   (f"{S}Foot", f"{S}Leg", *point("ankle", side), "feet")]
        ends[f"{S}Foot"] = point("toe", side)
    joints += [("Spine", "Hips", "thorax", zero, "thorax"),
               ("Neck", "Spine", *point("neck_base"), "head"),
               ("Head", "Neck", *point("head_joint"), "head")]
    ends["Head"] = point("head_top")
    for side, S in SIDE_NAMES.items():
        hand = f"{side}_hand"
        joints += [(f"{S}Shoulder", "Spine", f"{side}_clavicle", zero, f"{side}_clavicle"),
                   (f"{S}Arm", f"{S}Shoulder", *point("shoulder", side), f"{side}_upper_arm"),
                   (f"{S}ForeArm", f"{S}Arm", *point("elbow", side),
                    f"{side}_forearm_pronation_link"),
                   (f"{S}Hand", f"{S}ForeArm", *point("wrist", side), hand),
                   (f"{S}HandMiddle1", f"{S}Hand", *point("hand", side), hand),
                   (f"{S}HandIndex1", f"{S}Hand", *point("index", side), hand),
                   (f"{S}HandPinky1", f"{S}Hand", *point("pinky", side), hand),
                   (f"{S}HandThumb1", f"{S}Hand", *point("thumb", side), hand)]
    return joints, ends


def twin_bvh(state: KinematicState, body: BodySpec, up: str = "y", units: str = "m",
             frame_time: float = 1 / 30, decimals: int = 10) -> str:
    """N twin postures as the text of a BVH file.

    Args:
        state: forward kinematics of the postures (the twin's world: x forward, y left, z up).
        body: the body the skeleton was built from.
        up: the axis that points up in the file (BVH's convention: ``y``; the twin's x then
            is the file's z and its y the file's x).
        units: the file's length unit, ``m``, ``cm`` or ``mm``.
        frame_time: seconds between frames.
        decimals: digits after the point in every number.

    Returns:
        The BVH text: root ``Hips`` at the pelvis with position channels, every joint with
        ZXY rotation channels.
    """
    joints, ends = twin_joints(body)
    return joints_bvh(state, joints, ends, up, units, frame_time, decimals)


def joints_bvh(state: KinematicState, joints: list[TwinJoint],
               ends: dict[str, tuple[str, tuple]], up: str = "y", units: str = "m",
               frame_time: float = 1 / 30, decimals: int = 10) -> str:
    """N twin postures as the text of a BVH file of any skeleton laid on the twin: ``joints``
    (:data:`TwinJoint`, parents first; a joint at its parent's point has a zero offset) and
    End Sites ``ends`` (joint -> twin link, offset); the other arguments as :func:`twin_bvh`'s.
    """
    scale = unit_scale(units, "the BVH file")
    model = state.model
    rest = model.forward(np.zeros((1, model.nq)))
    names = [j[0] for j in joints]
    parents = [names.index(j[1]) if j[1] else -1 for j in joints]
    turn = to_axes(np.eye(3), up).T  # file vector = turn @ twin vector
    rest_at = np.array([rest.point(link, offset)[0] for _, _, link, offset, _ in joints])
    offsets = np.array([rest_at[j] - rest_at[p] if p >= 0 else np.zeros(3)
                        for j, p in enumerate(parents)])
    end_sites = {names.index(joint): turn @ (rest.point(link, offset)[0] - rest_at[
        names.index(joint)]) * scale for joint, (link, offset) in ends.items()}
    rotations = np.stack([state.rotation(j[4]) for j in joints], axis=1)  # (N, J, 3, 3)
    parent_rot = np.stack([rotations[:, p] if p >= 0 else np.broadcast_to(
        np.eye(3), rotations[:, 0].shape) for p in parents], axis=1)
    local = np.swapaxes(parent_rot, -1, -2) @ rotations
    angles = zxy_angles(turn @ local @ turn.T)
    roots = state.position("pelvis") @ turn.T * scale
    return bvh_text(names, parents, offsets @ turn.T * scale, angles, roots, frame_time,
                    end_sites, decimals)
