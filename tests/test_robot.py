"""The box URDF and the dual-arm robot's reachability: distances and reasons."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ergohandover.frames import worker_to_world
from ergohandover.scene.box import box_urdf_text, cached_box_urdf, robot_grasp_offset
from ergohandover.scene.robot import ARMS, GRASP_LINK, REASONS, RobotSpec, RobotSpecError
from ergohandover.scene.world import WorkerPosture, World
from ergohandover.twin.evaluate import Evaluator, posture_solver
from ergohandover.twin.task import TaskSpec

# Corners and centre of the paper-code boundary (worker frame [m]).
PAPER_CODE_POINTS = [(0.0, 1.08, 0.45), (-0.2, 0.72, 0.3), (0.2, 0.72, 0.6), (-0.2, 1.44, 0.6),
                     (0.2, 1.44, 0.3), (0.001, 1.173, 0.375)]


@pytest.fixture(scope="module")
def world():
    scene = World()
    try:
        yield scene
    finally:
        scene.close()


@pytest.fixture(scope="module")
def postures():
    """The twin's posture at a location, from the whole-body solver."""
    solver = posture_solver(Evaluator())

    def at(location):
        q = solver.solve(np.asarray(location, float)[None]).q[0]
        return WorkerPosture(solver.model.joint_names, q)

    return at


def link_position(world: World, body: int, link: int) -> np.ndarray:
    return np.array(world.p.getLinkState(body, link, computeForwardKinematics=True,
                                         physicsClientId=world.client)[4])


def test_box_frames_are_the_task_handles_and_the_grasps_behind_them(world):
    location = np.array([0.05, 1.2, 0.4])
    world.place_box(location)
    left, right = TaskSpec().handles(location[None])
    for side, grip in (("left", left[0]), ("right", right[0])):
        at = link_position(world, world.box.body_id, world.box.links[f"{side}_grip"])
        assert np.allclose(at, worker_to_world(grip), atol=1e-6)
        grasp = link_position(world, world.box.body_id, world.box.links[f"{side}_robot_grasp"])
        # Toward the robot (world +x) along the rail, beyond the box's back face.
        assert np.allclose(grasp - at, [robot_grasp_offset(TaskSpec()), 0, 0], atol=1e-6)
        assert robot_grasp_offset(TaskSpec()) > TaskSpec().box_depth / 2


def test_box_urdf_follows_the_task_and_is_cached(tmp_path):
    small = TaskSpec(box_width=0.30, box_depth=0.20, handle_span=0.34, box_mass_kg=3.0)
    assert box_urdf_text(small) != box_urdf_text()
    assert '<box size="0.2 0.3 0.25"/>' in box_urdf_text(small)
    first = cached_box_urdf(small, tmp_path)
    assert cached_box_urdf(small, tmp_path) == first and first.read_text() == box_urdf_text(small)


@pytest.mark.parametrize("location", PAPER_CODE_POINTS)
def test_ik_puts_both_grippers_within_1cm_of_their_handles(world, postures, location):
    reach = world.reach(np.array(location), postures(location))
    assert reach.reachable, reach.reason
    assert reach.reason == ""
    for arm in ARMS:
        # Read from the robot's own URDF body, not from the IK's twin arms.
        robot, grasp = world.robot.body, world.robot.body_links[f"{arm}_{GRASP_LINK}"]
        gripper = link_position(world, robot, grasp)
        handle = link_position(world, world.box.body_id, world.box.links[f"{arm}_robot_grasp"])
        assert np.linalg.norm(gripper - handle) < 0.01
        # The fingers close vertically: the box hangs level between them.
        state = world.p.getLinkState(robot, grasp, physicsClientId=world.client)
        closing = np.array(world.p.getMatrixFromQuaternion(state[5])).reshape(3, 3)[:, 1]
        assert abs(closing[2]) > math.cos(math.radians(3))
        q = reach.q[arm]
        assert np.all(q >= world.robot.lower) and np.all(q <= world.robot.upper)
    assert world.robot.collisions(world.box.body_id, world.worker.body_id) == []


@pytest.mark.parametrize("location", [(0.0, 2.6, 0.4), (0.0, 1.1, 2.4), (1.6, 1.1, 0.4)])
def test_a_location_out_of_reach_gets_a_reason(world, location):
    reach = world.reach(np.array(location))
    assert not reach.reachable
    assert reach.reason in REASONS
    assert reach.reason == "robot_ik" and reach.error_m > 0.01


def test_a_box_inside_the_stand_is_a_collision(world):
    spec = RobotSpec()
    inside = np.array([0.0, spec.mount_height / 2, spec.distance])  # worker frame
    reach = world.reach(inside)
    assert not reach.reachable
    assert "robot_collision_box" in reach.reason or "robot_ik" in reach.reason
    world.robot.set_arm("left", world.robot.rest["left"])
    world.robot.set_arm("right", world.robot.rest["right"])
    assert "robot_collision_box" in world.robot.collisions(world.box.body_id)


def test_arms_inside_the_worker_are_a_worker_collision():
    close = World(robot=RobotSpec(distance=1.2, drive_range=0.7, arm_spacing=0.5))
    try:
        close.pose_worker(None)
        close.robot.set_base(0.0, 0.7)  # driven to half a metre from the worker
        out = np.array([0.0, 1.5, 0.0, -0.1, 0.0, 1.6, 0.0])  # stretched out horizontally
        for arm in ARMS:
            close.robot.set_arm(arm, out)
        # From half a metre the stretched arms pass through the standing worker.
        assert close.robot.collisions(worker=close.worker.body_id) == ["robot_collision_worker"]
    finally:
        close.close()


def test_robot_at_rest_far_from_the_worker_touches_nothing(world):
    world.pose_worker(None)
    world.place_box(np.array([0.0, 3.0, 0.0]))  # out of the way
    for arm in ARMS:
        world.robot.set_arm(arm, world.robot.rest[arm])
    assert world.robot.collisions(world.box.body_id, world.worker.body_id) == []


def test_robot_spec_rejects_values_outside_their_range():
    with pytest.raises(RobotSpecError,
                       match=r"distance = 0.1 is outside the valid range 0.8-2.5"):
        RobotSpec(distance=0.1)
    with pytest.raises(RobotSpecError, match="mount_height = nan"):
        RobotSpec(mount_height=float("nan"))


def test_the_base_drives_to_keep_the_box_at_arms_length(world):
    spec = world.robot.spec
    for z in (0.4, 0.8, 1.2):  # worker frame: the box this far in front of the worker
        world.bring_robot(np.array([0.0, 1.0, z]), lift=0.2)
        bases = [link_position(world, world.robot.body, world.robot.body_links[
            f"{arm}_panda_link0"]) for arm in ARMS]
        expected = min(max(z + spec.carry_reach, spec.distance - spec.drive_range),
                       spec.distance)
        assert all(math.isclose(base[0], expected, abs_tol=1e-6) for base in bases)
        assert all(math.isclose(base[2], spec.mount_height + 0.2, abs_tol=1e-6)
                   for base in bases)
