"""Solved joint state -> the Posture columns, in the REBA worksheet's conventions.

Trunk flexion and side bend are measured from vertical (or, as an option, relative to the
pelvis); neck and upper arm relative to the
trunk; knees, elbows and wrists from their joints. Degrees, flexion positive. The world frame
has x forward, y to the worker's left, z up.
"""

from __future__ import annotations

import numpy as np

from .kinematics import KinematicState
from .task import TaskSpec

# RULA's lower-arm "+1 out to the side": the grip this far beyond its shoulder joint [m].
OUT_TO_SIDE_M = 0.10


def _deg(x: np.ndarray) -> np.ndarray:
    return np.degrees(x)


def _lean(up: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Flexion (forward, sagittal) and side bend (to the right) of an up-axis, (N, 3) -> deg."""
    flexion = np.arctan2(up[:, 0], up[:, 2])
    side_bend = np.arcsin(np.clip(-up[:, 1], -1.0, 1.0))
    return _deg(flexion), _deg(side_bend)


def posture_columns(st: KinematicState, task: TaskSpec,
                    trunk_reference: str = "vertical") -> dict[str, np.ndarray]:
    """The Posture columns of N solved postures.

    Args:
        st: forward kinematics of the solved postures.
        task: gives load, coupling and activity.
        trunk_reference: trunk flexion and side bend from ``vertical`` (the worksheets') or
            relative to the ``pelvis``.

    Returns:
        Column name -> (N,) array, every column of :data:`ergonomics.POSTURE_COLUMNS`.
    """
    model, q = st.model, st.q
    n = q.shape[0]

    def joint(name: str) -> np.ndarray:
        return _deg(q[:, model.index(name)])

    thorax = st.rotation("thorax")  # (N, 3, 3), columns = thorax axes in the world
    to_thorax = thorax.transpose(0, 2, 1)
    cols: dict[str, np.ndarray] = {}
    trunk_up = thorax[:, :, 2]
    if trunk_reference == "pelvis":
        trunk_up = (st.rotation("pelvis").transpose(0, 2, 1) @ thorax)[:, :, 2]
    cols["trunk_flexion"], cols["trunk_side_bend"] = _lean(trunk_up)
    cols["trunk_twist"] = joint("lumbar_twist")
    head_up = (to_thorax @ st.rotation("head"))[:, :, 2]
    cols["neck_flexion"], cols["neck_side_bend"] = _lean(head_up)
    cols["neck_twist"] = joint("neck_twist")
    cols["left_knee_flexion"] = cols["right_knee_flexion"] = joint("knee_flexion")
    neck_height = st.position("neck_flexion_link")[:, 2]
    grips_z = np.maximum(st.point("left_grip")[:, 2], st.point("right_grip")[:, 2])
    load = np.full(n, task.box_mass_kg)
    cols.update(
        bilateral_support=np.ones(n), seated=np.zeros(n), load_kg=load,
        shock=np.zeros(n), coupling=np.full(n, float(task.coupling)),
        activity=np.full(n, float(task.activity)), muscle_use=np.zeros(n),
        neck_trunk_legs_muscle_use=np.zeros(n), neck_trunk_legs_load_kg=load.copy(),
        hands_above_neck=(grips_z > neck_height).astype(float),
    )
    for side, outward in (("left", 1.0), ("right", -1.0)):
        shoulder = st.position(f"{side}_shoulder_flexion_link")
        arm = (to_thorax @ (st.position(f"{side}_forearm") - shoulder)[..., None])[..., 0]
        arm /= np.linalg.norm(arm, axis=1, keepdims=True)
        grip = (to_thorax @ (st.point(f"{side}_grip") - shoulder)[..., None])[..., 0]
        grip_mid = (to_thorax @ (st.point(f"{side}_grip")
                                 - st.position("thorax"))[..., None])[..., 0]
        cols[f"{side}_upper_arm_flexion"] = _deg(np.arctan2(arm[:, 0], -arm[:, 2]))
        cols[f"{side}_upper_arm_abduction"] = _deg(np.arcsin(np.clip(outward * arm[:, 1], -1, 1)))
        cols[f"{side}_upper_arm_rotation"] = joint(f"{side}_shoulder_rotation")
        # The joint's zero is this body's own resting clavicle (its shoulder drop over its
        # clavicle length), so the raise is measured from the body's neutral, + up, - down.
        cols[f"{side}_shoulder_raise"] = joint(f"{side}_clavicle_elevation")
        cols[f"{side}_elbow_flexion"] = joint(f"{side}_elbow_flexion")
        cols[f"{side}_wrist_flexion"] = joint(f"{side}_wrist_flexion")
        cols[f"{side}_wrist_deviation"] = joint(f"{side}_wrist_deviation")
        cols[f"{side}_wrist_twist"] = joint(f"{side}_forearm_pronation")
        cols[f"{side}_arm_supported"] = np.zeros(n)
        across = outward * grip_mid[:, 1] < 0.0
        out_to_side = outward * grip[:, 1] > OUT_TO_SIDE_M
        cols[f"{side}_arm_across_midline"] = (across | out_to_side).astype(float)
    return cols
