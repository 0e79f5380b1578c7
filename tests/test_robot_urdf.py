"""The robot's one URDF: committed for the default spec, loadable in plain PyBullet, and the
body the scene drives (its lift raises both arms, and the IK's twin arms follow)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pybullet as p
import pytest

from ergohandover.scene.robot import ARM_JOINTS, ARMS, GRASP_LINK, RobotSpec, RobotSpecError
from ergohandover.scene.robot_urdf import PANDA_PACKAGE, resolve_packages, robot_urdf
from ergohandover.scene.world import World

ROOT = Path(__file__).resolve().parents[1]
COMMITTED = ROOT / "urdf" / "robot_default.urdf"


def test_the_committed_robot_urdf_is_the_default_specs():
    assert COMMITTED.read_text() == robot_urdf(RobotSpec())
    assert robot_urdf(RobotSpec(mount_height=0.8)) != robot_urdf(RobotSpec())
    assert PANDA_PACKAGE + "meshes/collision/link0.obj" in COMMITTED.read_text()


def test_plain_pybullet_loads_it_with_a_lift_and_two_named_arms(tmp_path):
    path = tmp_path / "robot.urdf"
    path.write_text(resolve_packages(COMMITTED.read_text()))
    client = p.connect(p.DIRECT)
    try:
        body = p.loadURDF(str(path), useFixedBase=True, physicsClientId=client)
        info = {p.getJointInfo(body, i, physicsClientId=client)[1].decode():
                p.getJointInfo(body, i, physicsClientId=client)
                for i in range(p.getNumJoints(body, physicsClientId=client))}
    finally:
        p.disconnect(client)
    lift = info["torso_lift"]
    assert lift[2] == p.JOINT_PRISMATIC and (lift[8], lift[9]) == (0.0, RobotSpec().lift_range)
    for arm in ARMS:
        for name in ARM_JOINTS:
            joint = info[f"{arm}_{name}"]
            assert joint[2] == p.JOINT_REVOLUTE and joint[8] < joint[9]
    movable = [n for n, j in info.items() if j[2] != p.JOINT_FIXED]
    assert len(movable) == 2 + 2 * (7 + 2)  # drive, lift, two arms, two fingers each


def test_the_lift_and_the_drive_move_both_arms_and_the_grasp_follows():
    with World() as world:
        robot = world.robot
        q = {arm: robot.rest[arm] for arm in ARMS}
        low = {arm: robot.grasp_pose(arm)[0] for arm in ARMS}
        robot.set_base(0.4, 0.3)
        for arm in ARMS:
            robot.set_arm(arm, q[arm])
            high = robot.grasp_pose(arm)[0]
            # Up by the lift, toward the worker (world -x) by the drive.
            np.testing.assert_allclose(high - low[arm], [-0.3, 0.0, 0.4], atol=1e-9)
            # The IK's twin arm stands IK_OFFSET below with the same pose.
            twin = p.getLinkState(robot.arms[arm], robot.links[arm][GRASP_LINK],
                                  computeForwardKinematics=True,
                                  physicsClientId=world.client)[4]
            np.testing.assert_allclose(np.array(twin) - high, [0.0, 0.0, -100.0], atol=1e-6)
        assert robot.joint_values()["torso_lift"] == pytest.approx(0.4)
        assert robot.joint_values()["base_drive"] == pytest.approx(0.3)


def test_a_lift_beyond_its_travel_is_a_one_line_error():
    with pytest.raises(RobotSpecError, match="lift_range"):
        RobotSpec(lift_range=2.0)
