"""Behaviour of the worker's skeleton and numpy kinematics: anatomy, signs, Jacobians, COM."""

from __future__ import annotations

import numpy as np
import pytest

from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.kinematics import KinematicModel
from ergohandover.twin.skeleton import PALM_NORMAL, build_skeleton

SIDES = ("left", "right")
BODIES = {"p50-male": BodySpec(), "p5-female": BodySpec.from_percentile("p5-female")}
ARM = (
    "clavicle_elevation", "shoulder_flexion", "shoulder_abduction", "shoulder_rotation",
    "elbow_flexion", "forearm_pronation", "wrist_flexion", "wrist_deviation",
)
AXIAL = (
    "ankle_flexion", "knee_flexion", "hip_flexion", "lumbar_flexion", "lumbar_side_bend",
    "lumbar_twist", "neck_flexion", "neck_side_bend", "neck_twist",
)
EXPECTED_ORDER = AXIAL + tuple(f"{s}_{j}" for s in SIDES for j in ARM)


@pytest.fixture(scope="module", params=list(BODIES))
def model(request) -> KinematicModel:
    return KinematicModel(build_skeleton(BODIES[request.param]))


@pytest.fixture(scope="module")
def p50() -> KinematicModel:
    return KinematicModel(build_skeleton(BodySpec()))


def pose(model: KinematicModel, **degrees: float) -> np.ndarray:
    """(1, nq) posture: zero except the named joints [deg]."""
    q = np.zeros((1, model.nq))
    for name, value in degrees.items():
        q[0, model.index(name)] = np.radians(value)
    return q


def random_q(model: KinematicModel, n: int, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).uniform(model.lower, model.upper, (n, model.nq))


def test_joint_order_is_the_documented_tree_order(p50):
    assert p50.joint_names == EXPECTED_ORDER
    assert [p50.index(n) for n in EXPECTED_ORDER] == list(range(25))


def test_limits_are_the_anthropometric_ranges_in_radians(model):
    limits = model.skeleton.body.joint_limits_deg()
    assert set(limits) == set(model.joint_names)
    for name, (lo, hi) in limits.items():
        assert model.lower[model.index(name)] == pytest.approx(np.radians(lo))
        assert model.upper[model.index(name)] == pytest.approx(np.radians(hi))


def test_tree_is_topological_and_masses_add_up(model):
    seen = {model.skeleton.links[0].name}
    for joint in model.skeleton.joints:
        assert joint.parent in seen
        seen.add(joint.child)
    assert seen == set(model.link_names)
    assert model.total_mass == pytest.approx(model.skeleton.body.mass_kg, rel=1e-9)


def test_unknown_names_and_bad_shapes_are_rejected(p50):
    with pytest.raises(KeyError, match="left_elbow_flexion"):
        p50.index("elbow")
    with pytest.raises(KeyError, match="no link"):
        p50.forward(np.zeros(p50.nq)).position("spine")
    with pytest.raises(ValueError, match="shape"):
        p50.forward(np.zeros((2, p50.nq + 1)))
    with pytest.raises(KeyError):
        p50.skeleton.joint("thorax")  # a link, not a joint


def test_standing_anatomy_matches_the_segments(model):
    body = model.skeleton.body
    s, h = body.segments(), body.stature_m
    fk = model.forward(np.zeros(model.nq))
    head = model.skeleton.link("head")
    sphere = next(shape for shape in head.shapes if shape.kind == "sphere")
    top = fk.point("head", np.add(sphere.xyz, (0.0, 0.0, sphere.size[0])))[0]
    assert top == pytest.approx([0.0, 0.0, h], abs=1e-3)
    eyes = s.neck_joint_height + s.neck_length + s.eye_height_above_head_joint
    assert fk.position("gaze")[0] == pytest.approx([s.eye_forward, 0.0, eyes], abs=1e-3)
    hand = model.skeleton.link("left_hand").shapes[0].size  # (breadth, thickness, length)
    for side, sign in (("left", 1.0), ("right", -1.0)):
        shoulder = fk.position(f"{side}_upper_arm")[0]
        assert shoulder == pytest.approx([0, sign * s.shoulder_width / 2, s.shoulder_height])
        grip = fk.position(f"{side}_grip")[0]
        # The wrist at the body's own wrist height (the survey's stylion, arm hanging).
        wrist = body.landmarks()["wrist_height_m"]
        assert grip == pytest.approx(
            [0, sign * s.shoulder_width / 2, wrist - s.grip_offset], abs=1e-3)
        # Beside the thigh, not inside it.
        assert abs(grip[1]) - hand[1] / 2 > s.hip_width / 2 + s.thigh_radius
        palm = fk.rotation(f"{side}_hand")[0] @ PALM_NORMAL[side]
        assert palm == pytest.approx([0, -sign, 0])  # palms face the thighs
        assert fk.rotation(f"{side}_hand")[0][:, 0] == pytest.approx([1, 0, 0])  # thumbs fwd


def test_feet_stay_at_the_origin_for_any_posture(model):
    fk = model.forward(random_q(model, 100))
    assert np.array_equal(fk.position("feet"), np.zeros((100, 3)))
    assert np.array_equal(fk.rotation("feet"), np.broadcast_to(np.eye(3), (100, 3, 3)))


def test_rotations_stay_orthonormal(model):
    rot = model.forward(random_q(model, 200)).rotations
    eye = np.broadcast_to(np.eye(3), rot.shape)
    assert np.abs(rot @ rot.swapaxes(-1, -2) - eye).max() < 1e-12
    assert np.linalg.det(rot) == pytest.approx(1.0)


def test_arms_mirror_each_other(model):
    """Same signed angles on both arms give postures mirrored in the sagittal plane."""
    q = random_q(model, 50, seed=3)
    for name in ("lumbar_side_bend", "lumbar_twist", "neck_side_bend", "neck_twist"):
        q[:, model.index(name)] = 0.0
    for joint in ARM:
        q[:, model.index(f"right_{joint}")] = q[:, model.index(f"left_{joint}")]
    fk = model.forward(q)
    mirror = np.diag([1.0, -1.0, 1.0])
    for link in ("upper_arm", "forearm", "hand", "grip"):
        left, right = fk.position(f"left_{link}"), fk.position(f"right_{link}")
        assert np.abs(left @ mirror - right).max() < 1e-12
        assert np.abs(mirror @ fk.rotation(f"left_{link}") @ mirror
                      - fk.rotation(f"right_{link}")).max() < 1e-12


def _moved(model, link, offset=(0.0, 0.0, 0.0), **degrees):
    """World displacement of a point fixed in ``link`` from standing to the posture."""
    return (model.forward(pose(model, **degrees)).point(link, offset)
            - model.forward(pose(model)).point(link, offset))[0]


def test_axial_sign_conventions(p50):
    assert _moved(p50, "shank", (0, 0, 0.4), ankle_flexion=10)[0] > 0  # knee goes forward
    assert _moved(p50, "pelvis", knee_flexion=30)[0] < 0  # thigh tips back over fixed feet
    assert _moved(p50, "head", hip_flexion=30)[0] > 0
    assert _moved(p50, "head", lumbar_flexion=30)[0] > 0
    assert _moved(p50, "gaze", neck_flexion=30)[0] > 0
    assert _moved(p50, "head", lumbar_side_bend=20)[1] < 0  # toward the worker's right
    assert _moved(p50, "gaze", neck_side_bend=20)[1] < 0
    for joint, link in (("lumbar_twist", "thorax"), ("neck_twist", "gaze")):
        forward = p50.forward(pose(p50, **{joint: 30})).rotation(link)[0][:, 0]
        assert forward == pytest.approx([np.cos(np.radians(30)), -np.sin(np.radians(30)), 0])


@pytest.mark.parametrize(("side", "sign"), [("left", 1.0), ("right", -1.0)])
def test_arm_sign_conventions(p50, side, sign):
    s = p50.skeleton.body.segments()
    j = {name: f"{side}_{name}" for name in ARM}
    reach = s.upper_arm_length + s.forearm_length + s.grip_offset
    grip = p50.forward(pose(p50, **{j["shoulder_flexion"]: 90})).position(f"{side}_grip")[0]
    assert grip == pytest.approx([reach, sign * s.shoulder_width / 2, s.shoulder_height])
    assert _moved(p50, f"{side}_upper_arm", **{j["clavicle_elevation"]: 20})[2] > 0
    assert sign * _moved(p50, f"{side}_grip", **{j["shoulder_abduction"]: 30})[1] > 0
    bent = {j["elbow_flexion"]: 90}
    fk = p50.forward(pose(p50, **bent))
    forearm = fk.position(f"{side}_wrist_flexion_link") - fk.position(f"{side}_forearm")
    assert forearm[0] == pytest.approx([s.forearm_length, 0, 0])
    # Internal rotation swings the bent forearm medially.
    assert sign * _moved(p50, f"{side}_grip", **bent, **{j["shoulder_rotation"]: 30})[1] < 0
    # Pronation turns the palm from medial to down, thumb from up to medial.
    for angle, palm_z in ((0, 0.0), (80, -np.sin(np.radians(80)))):
        hand = p50.forward(pose(p50, **bent, **{j["forearm_pronation"]: angle}))
        palm = hand.rotation(f"{side}_hand")[0] @ PALM_NORMAL[side]
        assert palm == pytest.approx([0, -sign * np.cos(np.radians(angle)), palm_z], abs=1e-12)
    tip = (0.0, 0.0, -s.hand_length)
    assert sign * _moved(p50, f"{side}_hand", tip, **{j["wrist_flexion"]: 30})[1] < 0  # to palm
    assert _moved(p50, f"{side}_hand", tip, **{j["wrist_deviation"]: 20})[0] < 0  # ulnar = back


def _central(f, q, eps=1e-6):
    """(N, ..., nq) central differences of f(q) [per rad]."""
    cols = []
    for j in range(q.shape[1]):
        step = np.zeros_like(q)
        step[:, j] = eps
        cols.append((f(q + step) - f(q - step)) / (2 * eps))
    return np.stack(cols, axis=-1)


def test_point_jacobians_match_finite_differences(model):
    q = random_q(model, 20, seed=1)
    fk = model.forward(q)
    offsets = np.random.default_rng(2).normal(0, 0.1, (20, 3))
    cases = [("left_grip", None), ("right_hand", (0.01, -0.02, -0.05)), ("gaze", offsets),
             ("thorax", None), ("feet", None)]
    for link, offset in cases:
        numeric = _central(lambda x, link=link, o=offset: model.forward(x).point(link, o), q)
        assert np.abs(fk.point_jacobian(link, offset) - numeric).max() < 1e-5
        assert np.array_equal(model.point_jacobian(q, link, offset),
                              fk.point_jacobian(link, offset))


def test_angular_jacobians_match_finite_differences(model):
    q = random_q(model, 20, seed=4)
    fk = model.forward(q)
    for link in ("left_hand", "right_forearm", "head", "pelvis"):
        rot = fk.rotation(link)
        d_rot = _central(lambda x, link=link: model.forward(x).rotation(link), q)
        # dR/dq_j R^T = [w_j]x; read w_j off the skew matrix.
        skew = np.einsum("nabj,ncb->nacj", d_rot, rot)
        omega = np.stack([skew[:, 2, 1], skew[:, 0, 2], skew[:, 1, 0]], axis=1)
        assert np.abs(fk.angular_jacobian(link) - omega).max() < 1e-5


def test_com_is_mass_weighted_and_its_jacobian_matches_finite_differences(model):
    q = random_q(model, 20, seed=5)
    box = np.linspace(0.0, 20.0, 20)  # per-posture box mass [kg]
    extra = {"left_grip": box / 2, "right_grip": box / 2}
    fk = model.forward(q)
    by_hand = sum(
        link.mass * fk.point(link.name, link.com) for link in model.skeleton.links
    ) + box[:, None] / 2 * (fk.position("left_grip") + fk.position("right_grip"))
    total = model.total_mass + box
    assert np.abs(fk.com(extra) - by_hand / total[:, None]).max() < 1e-12
    for masses in (None, extra):
        numeric = _central(lambda x, m=masses: model.forward(x).com(m), q)
        assert np.abs(fk.com_jacobian(masses) - numeric).max() < 1e-5
    assert np.array_equal(model.com(q, extra), fk.com(extra))
    assert np.array_equal(model.com_jacobian(q), fk.com_jacobian())


def test_standing_com_is_over_the_feet(p50):
    com = p50.com(np.zeros(p50.nq))[0]
    foot = p50.skeleton.body.segments()
    assert -foot.heel_to_ankle < com[0] < foot.foot_length - foot.heel_to_ankle
    assert com[1] == pytest.approx(0.0, abs=1e-12)
    assert 0.5 * p50.skeleton.body.stature_m < com[2] < 0.6 * p50.skeleton.body.stature_m
