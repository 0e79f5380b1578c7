"""A twin that takes an object in one hand, and a twin sized from measured segment lengths: the
taking hand reaches the object, the other arm is free, the object's weight sits in the taking
hand, the two sides mirror each other, both solvers agree, and a body built from segment
lengths has those segments."""

from __future__ import annotations

import numpy as np
import pytest

from ergohandover.frames import worker_to_world
from ergohandover.twin.anthropometry import BodySpecError
from ergohandover.twin.evaluate import EvaluationError, Evaluator, evaluate
from ergohandover.twin.segment_sizing import body_from_segments
from ergohandover.twin.solver import PostureSolver
from ergohandover.twin.task import OBJECTS, TaskSpec, TaskSpecError

POINTS = np.array([[-0.25, 1.30, 0.35], [-0.15, 1.10, 0.45], [0.0, 1.20, 0.30],
                   [0.20, 0.95, 0.40]])
"""Object centres (worker frame) in reach of either hand."""


@pytest.fixture(scope="module")
def right():
    return evaluate(POINTS, Evaluator(task=TaskSpec.holding("bottle", hands="right")),
                    joints=True)


def test_the_taking_hand_reaches_the_object_and_the_other_hangs_free(right):
    assert (right["feasible"] == 1).all()
    assert (right["hand_error_m"] < 0.002).all()
    # The free arm holds nothing: it stays near its neutral, the upper arm down by the side.
    assert (right["left_upper_arm_flexion"].abs() < 25).all()
    solver = PostureSolver(task=TaskSpec.holding("bottle", hands="right"))
    solution = solver.iterate(POINTS, np.tile(solver.strategy_start("stoop"), (len(POINTS), 1)),
                              100)
    free = np.linalg.norm(solution.state.point("left_grip") - worker_to_world(POINTS), axis=1)
    assert (free > 0.15).all()


@pytest.mark.slow
def test_left_is_the_mirror_of_right(right):
    mirrored = POINTS * np.array([-1.0, 1.0, 1.0])
    left = evaluate(mirrored, Evaluator(task=TaskSpec.holding("bottle", hands="left")))
    for column in ("upper_arm_flexion", "upper_arm_abduction", "elbow_flexion"):
        assert np.allclose(left[f"left_{column}"], right[f"right_{column}"], atol=0.05), column
    for column in ("trunk_flexion", "neck_flexion", "reba", "rula", "paper_postural"):
        assert np.allclose(left[column], right[column], atol=0.05), column
    assert np.allclose(left["trunk_side_bend"], -right["trunk_side_bend"], atol=0.05)


@pytest.mark.slow
def test_the_compiled_and_the_numpy_solver_agree_one_handed():
    task = TaskSpec.holding("bottle", hands="right", box_mass_kg=3.0)
    compiled, reference = PostureSolver(task=task), PostureSolver(task=task, backend="numpy")
    start = compiled.lattice.start(POINTS)
    a = compiled.iterate(POINTS, start, 10)
    b = reference.iterate(POINTS, start, 10)
    assert np.abs(a.q - b.q).max() < 1e-6
    assert np.allclose(a.hand_error, b.hand_error, atol=1e-9)
    assert np.allclose(a.com, b.com, atol=1e-9)


def test_the_object_weighs_on_the_taking_side_only():
    point = POINTS[:1]
    com = {}
    for hands in ("left", "right"):
        for mass in (0.0, 10.0):
            solver = PostureSolver(task=TaskSpec.holding("bottle", hands=hands,
                                                         box_mass_kg=mass))
            # From standing, as the lattice's nodes are solved (no lattice needed for one).
            solution = solver.iterate(point, solver.strategy_start("stoop")[None], 100)
            com[hands, mass] = solution.com[0]
            state = solution.state
            # The weight is where the taking hand is: the centre of mass moves toward it.
            grip = state.point(f"{hands}_grip")[0]
            if mass:
                shift = com[hands, mass] - com[hands, 0.0]
                assert np.dot(shift[:2], (grip - com[hands, 0.0])[:2]) > 0
    assert PostureSolver(task=TaskSpec(hands="right", box_mass_kg=4.0)).grip_loads() == {
        "left_grip": 0.0, "right_grip": 4.0}
    assert PostureSolver(task=TaskSpec(box_mass_kg=4.0)).grip_loads() == {
        "left_grip": 2.0, "right_grip": 2.0}


def test_objects_and_refusals():
    assert TaskSpec.holding("box") == TaskSpec()
    bottle = TaskSpec.holding("bottle", hands="right")
    assert bottle.box_mass_kg == OBJECTS["bottle"]["box_mass_kg"] and bottle.hands == "right"
    with pytest.raises(TaskSpecError, match="object = 'anvil' is not allowed"):
        TaskSpec.holding("anvil")
    with pytest.raises(TaskSpecError, match="hands = 'both hands'"):
        TaskSpec(hands="both hands")
    # A narrow object held in one hand needs no handle span; with both hands it does.
    TaskSpec(box_width=0.5, handle_span=0.4, hands="right")
    with pytest.raises(TaskSpecError, match="handle_span"):
        TaskSpec(box_width=0.5, handle_span=0.4)
    with pytest.raises(EvaluationError, match="hands = 'right' is not allowed with solver"):
        Evaluator(task=TaskSpec(hands="right"), solver="pybullet")


@pytest.mark.parametrize("given", [{}, {"stature_m": 1.62}, {"shoulder_height_m": 1.33}])
def test_a_body_sized_from_segments_has_those_segments(given):
    lengths = {"thigh": 0.40, "shank": 0.356, "upper_arm": 0.269, "forearm": 0.262}
    body = body_from_segments(lengths, **given)
    seg = body.segments()
    for name, value in lengths.items():
        assert getattr(seg, f"{name}_length") == pytest.approx(value, abs=2e-4), name
    for name, value in given.items():
        assert body.landmarks()[name] == pytest.approx(value, abs=1e-3)
    # Longer measured legs make a taller body when nothing else is known.
    if not given:
        longer = body_from_segments({**lengths, "thigh": 0.46, "shank": 0.42})
        assert longer.stature_m > body.stature_m + 0.05


def test_an_unknown_segment_is_refused():
    with pytest.raises(BodySpecError, match="segment 'neck' is not known"):
        body_from_segments({"neck": 0.1})
