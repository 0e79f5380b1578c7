"""The carry planner: detours, reasons, determinism, path files replayed in plain PyBullet."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ergohandover.scene.carries import CarryJob, path_table, plan_carries, plan_seeds, replay
from ergohandover.scene.planner import MAX_JOINT_STEP_RAD, CarryPlanner, PlannerError
from ergohandover.scene.robot_collision import touches
from ergohandover.scene.world import World

ROOT = Path(__file__).resolve().parents[1]
ROBOT_URDF = ROOT / "urdf" / "robot_default.urdf"
# From the worker's right to its left, 0.2 m in front of its feet at hip height: the straight
# line drags the box through the standing worker's thighs and hands.
AROUND = CarryJob(np.array([-0.4, 0.8, 0.2]), np.array([0.4, 0.8, 0.2]))
SHORT = CarryJob(np.array([0.0, 1.1, 0.6]), np.array([0.0, 1.1, 0.45]))


@pytest.fixture(scope="module")
def detour():
    return next(plan_carries([AROUND], workers=1))


def box_touches_worker(world: World, location) -> bool:
    world.place_box(np.asarray(location, dtype=float))
    return touches(world.p, world.box.body_id, world.worker.body_id, world.client)


@pytest.mark.slow
def test_a_carry_blocked_by_the_worker_goes_around_it(detour):
    with World() as world:
        world.pose_worker(None)
        line = [AROUND.start + f * (AROUND.location - AROUND.start)
                for f in np.linspace(0.0, 1.0, 41)]
        assert any(box_touches_worker(world, point) for point in line)
        assert detour.ok, detour.reason
        points = np.array([w.location for w in detour.waypoints])
        assert np.allclose(points[0], AROUND.start) and np.allclose(points[-1], AROUND.location)
        assert not any(box_touches_worker(world, point) for point in points[:-1])
        # Away from the worker: the detour is longer than the line and keeps the robot clear.
        straight = np.linalg.norm(AROUND.location - AROUND.start)
        assert detour.length_m > 1.1 * straight and points[:, 2].max() > AROUND.start[2] + 0.05
        assert detour.clearance_m > 0.0


@pytest.mark.slow
def test_the_path_file_replays_in_plain_pybullet_without_collision_or_jumps(detour, tmp_path):
    with World() as world:
        table = path_table(world, detour)
    table.to_csv(tmp_path / "carry.csv", index=False)
    played = replay(pd.read_csv(tmp_path / "carry.csv"), ROBOT_URDF)
    assert played.self_penetration_m <= 0.005
    assert played.revolute_step_rad <= MAX_JOINT_STEP_RAD
    assert played.prismatic_step_m <= 0.03  # the lift and the drive, 2 cm box steps at most
    times = table["time"].to_numpy()
    assert times[0] == 0.0 and np.all(np.diff(times) > 0)


@pytest.mark.slow
def test_a_start_out_of_reach_is_a_reason_not_a_path():
    plan = next(plan_carries([CarryJob(np.array([0.0, 3.0, 0.6]), SHORT.location)]))
    assert not plan.ok and plan.waypoints == []
    assert plan.reason.startswith("unreachable_start: robot_ik")
    plan = next(plan_carries([CarryJob(SHORT.start, np.array([1.6, 1.1, 0.4]))]))
    assert plan.reason.startswith("unreachable_handover: robot_ik")


@pytest.mark.slow
def test_planning_is_deterministic_for_a_seed():
    # The short carry and one that must leave the line (planned or not within the budget,
    # it is the same answer every time).
    jobs = [SHORT, AROUND]
    first, again, other = (list(plan_carries(jobs, seed=seed, workers=2, budget=300))
                           for seed in (7, 7, 8))
    assert plan_seeds(7, 2) != plan_seeds(8, 2)
    for a, b in zip(first, again, strict=True):
        assert a.reason == b.reason and a.checks == b.checks and a.grasp == b.grasp
        assert len(a.waypoints) == len(b.waypoints)
        for u, v in zip(a.waypoints, b.waypoints, strict=True):
            assert np.array_equal(u.location, v.location) and u.lift == v.lift
            assert all(np.array_equal(u.q[arm], v.q[arm]) for arm in u.q)
    assert other[0].ok  # another seed plans the short carry too


def test_planner_settings_are_checked():
    with World() as world:
        with pytest.raises(PlannerError, match=r"budget = 10 is outside 100-1000000"):
            CarryPlanner(world, budget=10)
        with pytest.raises(PlannerError, match=r"seed = -1 is not allowed"):
            CarryPlanner(world, seed=-1)
