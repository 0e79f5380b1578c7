"""The worker's joint tree, built from a BodySpec: the one description that both the URDF writer
and the numpy kinematic model read, so the two cannot disagree.

Frames: every link frame sits on the joint that moves it and, at q = 0 (standing upright, arms
hanging, palms facing the thighs, thumbs forward), is aligned with the world (z up, facing +x,
left = +y). Joint origins are therefore plain offsets and every joint's ``rpy`` is zero; axes
are unit vectors in the child frame, signed so a positive angle moves the way the joint's name
says (``docs/anthropometry.md``); left and right arms share those signed conventions, so equal
angles give mirrored postures. The legs are mirrored too: one chain whose ``shank`` and
``thigh`` links carry both legs, so the feet never leave the floor.

Links, root first: ``feet``, ``shank``, ``thigh``, ``pelvis``, ``thorax``, ``head`` with the
fixed ``gaze`` (x = line of sight); per side ``{side}_clavicle``, ``{side}_upper_arm``,
``{side}_forearm``, ``{side}_hand`` with the fixed ``{side}_grip`` (power-grip centre). Joints
that share a centre are chained through massless links named ``{joint}_link``. Pronation:
with the elbow at 90° and the forearm along +x, a positive angle turns the palm from facing
medially to facing down, on both sides.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import ModelError, UnknownNameError
from .anthropometry import BodySpec

Vec3 = tuple[float, float, float]
SIDE_SIGN = {"left": 1.0, "right": -1.0}  # sign of y on each side; mirrored axes use it
PALM_NORMAL: dict[str, Vec3] = {"left": (0.0, -1.0, 0.0), "right": (0.0, 1.0, 0.0)}
"""Outward normal of each palm in its ``{side}_hand`` frame (thumb along +x)."""

# Colour families (RGBA) so renders read at a glance; shades separate neighbouring links.
SKIN = (0.87, 0.69, 0.56, 1.0)
SHIRT = (0.16, 0.42, 0.72, 1.0)
SHIRT_LIGHT = (0.26, 0.54, 0.84, 1.0)
TROUSERS = (0.24, 0.25, 0.30, 1.0)
TROUSERS_LIGHT = (0.34, 0.35, 0.41, 1.0)
BOOTS = (0.28, 0.17, 0.08, 1.0)
_BALL_OF_FOOT = 0.73  # estimate: metatarsal II head from the heel [fraction of foot length]


@dataclass(frozen=True)
class Shape:
    """One collision-and-visual primitive of a link.

    Attributes:
        kind: ``box``, ``capsule`` or ``sphere``.
        size: box: full extents (x, y, z) [m]; capsule: (radius, cylinder length) [m], axis
            along the shape's z; sphere: (radius,) [m].
        xyz: Centre in the link frame [m].
        rgba: Colour.
        rpy: Orientation in the link frame (roll, pitch, yaw) [rad].
    """

    kind: str
    size: tuple[float, ...]
    xyz: Vec3
    rgba: tuple[float, float, float, float]
    rpy: Vec3 = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Link:
    """A rigid body: mass [kg], COM [m] and principal inertia about it [kg m²], link frame."""

    name: str
    mass: float = 0.0
    com: Vec3 = (0.0, 0.0, 0.0)
    inertia: Vec3 = (0.0, 0.0, 0.0)  # (ixx, iyy, izz); products are zero by symmetry
    shapes: tuple[Shape, ...] = ()


@dataclass(frozen=True)
class Joint:
    """A joint: ``origin`` [m] places the child frame in the parent frame; limits [rad]."""

    name: str
    parent: str
    child: str
    origin: Vec3
    axis: Vec3 = (0.0, 0.0, 0.0)  # child frame; zero for a fixed joint
    lower: float = 0.0
    upper: float = 0.0
    type: str = "revolute"  # or "fixed"


@dataclass(frozen=True)
class Skeleton:
    """The worker's tree. ``links[0]`` is the fixed base; a joint's parent precedes it."""

    body: BodySpec
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    _by_name: dict[str, Link | Joint] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        """Index links and joints by name (their names share one namespace)."""
        by_name = {item.name: item for item in (*self.links, *self.joints)}
        if len(by_name) != len(self.links) + len(self.joints):
            raise ModelError("link and joint names must be unique")
        object.__setattr__(self, "_by_name", by_name)

    @property
    def movable_joints(self) -> tuple[Joint, ...]:
        """The revolute joints, in tree order (the kinematic model's q order)."""
        return tuple(j for j in self.joints if j.type != "fixed")

    def link(self, name: str) -> Link:
        """The link called ``name`` (KeyError if there is none)."""
        item = self._by_name[name]
        if not isinstance(item, Link):
            raise UnknownNameError(f"{name!r} is a joint, not a link")
        return item

    def joint(self, name: str) -> Joint:
        """The joint called ``name`` (KeyError if there is none)."""
        item = self._by_name[name]
        if not isinstance(item, Joint):
            raise UnknownNameError(f"{name!r} is a link, not a joint")
        return item


def _solid_inertia(kind: str, mass: float, dims: tuple[float, ...]) -> Vec3:
    """Principal inertia [kg m²] of a uniform solid about its centre; dims [m] as in Shape."""
    if kind == "box":
        a, b, c = dims
        return (mass * (b * b + c * c) / 12, mass * (a * a + c * c) / 12,
                mass * (a * a + b * b) / 12)
    if kind == "cylinder":  # (radius, length), axis z
        r, length = dims
        transverse = mass * (3 * r * r + length * length) / 12
        return (transverse, transverse, mass * r * r / 2)
    r = dims[0]  # sphere
    return (0.4 * mass * r * r,) * 3


def _pair(inertia: Vec3, mass_each: float, half_width: float) -> Vec3:
    """Inertia of two copies of a solid at y = ±half_width (parallel axis on x and z)."""
    shift = mass_each * half_width**2
    return (2 * inertia[0] + 2 * shift, 2 * inertia[1], 2 * inertia[2] + 2 * shift)


def _capsule(radius: float, z_from: float, z_to: float, rgba, y: float = 0.0) -> Shape:
    """A vertical capsule whose rounded ends reach half a radius past ``z_from`` and ``z_to``.

    The overhang hides the seam at a bent joint without poking far into the next segment.
    """
    length = max(abs(z_to - z_from) - radius, 0.0)
    return Shape("capsule", (radius, length), (0.0, y, (z_from + z_to) / 2), rgba)


def build_skeleton(body: BodySpec | None = None) -> Skeleton:
    """The worker's joint tree for ``body`` (default: ANSUR II 50th-percentile man).

    Args:
        body: Worker size; lengths [m], masses [kg] and limits [deg] come from it.

    Returns:
        The skeleton, base link ``feet`` at the world origin, limits in [rad].
    """
    body = body or BodySpec()
    s = body.segments()
    m = {name: seg.mass_kg for name, seg in body.segment_masses().items()}
    frac = {name: seg.com_fraction for name, seg in body.segment_masses().items()}
    limits = {n: (math.radians(lo), math.radians(hi))
              for n, (lo, hi) in body.joint_limits_deg().items()}
    links: list[Link] = []
    joints: list[Joint] = []

    def add(joint: str, parent: str, origin: Vec3, axis: Vec3, child: Link) -> None:
        kind = "fixed" if axis == (0.0, 0.0, 0.0) else "revolute"
        lo, hi = limits[joint] if kind == "revolute" else (0.0, 0.0)
        joints.append(Joint(joint, parent, child.name, origin, axis, lo, hi, kind))
        links.append(child)

    hw = s.hip_width / 2
    # Feet: boxes from heel to toe; COM halfway from the ankle to the ball of the foot.
    ball_x = _BALL_OF_FOOT * s.foot_length - s.heel_to_ankle
    foot_box = (s.foot_length, s.foot_width, s.ankle_height)
    foot_x = s.foot_length / 2 - s.heel_to_ankle
    links.append(Link(
        "feet", 2 * m["foot"], (frac["foot"] * ball_x, 0.0, (1 - frac["foot"]) * s.ankle_height),
        _pair(_solid_inertia("box", m["foot"], foot_box), m["foot"], hw),
        tuple(Shape("box", foot_box, (foot_x, y, s.ankle_height / 2), BOOTS) for y in (hw, -hw)),
    ))
    # Legs: each link carries both legs; com_fraction is measured down from the proximal joint.
    for name, parent, length, radius, at, axis, rgba in (
        ("shank", "feet", s.shank_length, s.shank_radius, s.ankle_height, 1.0, TROUSERS_LIGHT),
        ("thigh", "shank", s.thigh_length, s.thigh_radius, s.shank_length, -1.0, TROUSERS),
    ):
        leg = _solid_inertia("cylinder", m[name], (radius, length))
        add(f"{'ankle' if name == 'shank' else 'knee'}_flexion", parent, (0.0, 0.0, at),
            (0.0, axis, 0.0), Link(
                name, 2 * m[name], (0.0, 0.0, (1 - frac[name]) * length), _pair(leg, m[name], hw),
                tuple(_capsule(radius, 0.0, length, rgba, y) for y in (hw, -hw))))
    pelvis_box = (s.trunk_depth, s.pelvis_width, 2 * s.pelvis_height)  # crotch below the hips
    add("hip_flexion", "thigh", (0.0, 0.0, s.thigh_length), (0.0, 1.0, 0.0), Link(
        "pelvis", m["pelvis"], (0.0, 0.0, frac["pelvis"] * s.pelvis_height),
        _solid_inertia("box", m["pelvis"], pelvis_box),
        (Shape("box", pelvis_box, (0.0, 0.0, 0.0), TROUSERS),)))
    # Spine and neck: three joints at one point, massless links between them.
    trunk_box = (s.trunk_depth, s.trunk_width, s.trunk_length)
    thorax = Link("thorax", m["trunk"], (0.0, 0.0, frac["trunk"] * s.trunk_length),
                  _solid_inertia("box", m["trunk"], trunk_box),
                  (Shape("box", trunk_box, (0.0, 0.0, s.trunk_length / 2), SHIRT),))
    head_span = s.neck_length + s.head_height  # C7/T1 to vertex
    head = Link("head", m["head_neck"], (0.0, 0.0, frac["head_neck"] * head_span),
                _solid_inertia("sphere", m["head_neck"], (s.head_radius,)), (
                    _capsule(0.6 * s.head_radius, 0.0, s.neck_length, SKIN),
                    Shape("sphere", (s.head_radius,), (0.0, 0.0, head_span - s.head_radius), SKIN)))
    for group, parent, at, last in (("lumbar", "pelvis", s.pelvis_height, thorax),
                                    ("neck", "thorax", s.trunk_length, head)):
        add(f"{group}_flexion", parent, (0.0, 0.0, at), (0.0, 1.0, 0.0),
            Link(f"{group}_flexion_link"))
        add(f"{group}_side_bend", f"{group}_flexion_link", (0.0, 0.0, 0.0), (1.0, 0.0, 0.0),
            Link(f"{group}_side_bend_link"))
        add(f"{group}_twist", f"{group}_side_bend_link", (0.0, 0.0, 0.0), (0.0, 0.0, -1.0), last)
    add("gaze_mount", "head", (s.eye_forward, 0.0, s.neck_length + s.eye_height_above_head_joint),
        (0.0, 0.0, 0.0), Link("gaze"))
    for side, sign in SIDE_SIGN.items():
        _add_arm(add, body, side, sign)
    return Skeleton(body, tuple(links), tuple(joints))


def _add_arm(add, body: BodySpec, side: str, sign: float) -> None:
    """Append one arm, thorax top to grip; ``sign`` mirrors the lateral axes (+1 = left)."""
    s = body.segments()
    m = {name: seg.mass_kg for name, seg in body.segment_masses().items()}
    frac = {name: seg.com_fraction for name, seg in body.segment_masses().items()}
    p = f"{side}_"
    zero = (0.0, 0.0, 0.0)
    ua, fa, hand = s.upper_arm_length, s.forearm_length, s.hand_length
    # The clavicle carries a shoulder-girdle capsule (massless: its mass is in the trunk's).
    span = math.hypot(s.clavicle_length, s.shoulder_drop)
    roll = math.atan2(-sign * s.clavicle_length, -s.shoulder_drop)  # turns z onto the bone
    girdle = Shape("capsule", (s.upper_arm_radius, span),
                   (0.0, sign * s.clavicle_length / 2, -s.shoulder_drop / 2), SHIRT,
                   (roll, 0.0, 0.0))
    add(p + "clavicle_elevation", "thorax", (0.0, 0.0, s.trunk_length), (sign, 0.0, 0.0),
        Link(p + "clavicle", shapes=(girdle,)))
    add(p + "shoulder_flexion", p + "clavicle", (0.0, sign * s.clavicle_length, -s.shoulder_drop),
        (0.0, -1.0, 0.0), Link(p + "shoulder_flexion_link"))
    add(p + "shoulder_abduction", p + "shoulder_flexion_link", zero, (sign, 0.0, 0.0),
        Link(p + "shoulder_abduction_link"))
    # Long-axis joints point distally on the left, proximally on the right, so that internal
    # rotation and pronation are positive on both sides.
    add(p + "shoulder_rotation", p + "shoulder_abduction_link", zero, (0.0, 0.0, -sign), Link(
        p + "upper_arm", m["upper_arm"], (0.0, 0.0, -frac["upper_arm"] * ua),
        _solid_inertia("cylinder", m["upper_arm"], (s.upper_arm_radius, ua)),
        (_capsule(s.upper_arm_radius, 0.0, -ua, SHIRT),)))
    add(p + "elbow_flexion", p + "upper_arm", (0.0, 0.0, -ua), (0.0, -1.0, 0.0), Link(
        p + "forearm", m["forearm"], (0.0, 0.0, -frac["forearm"] * fa),
        _solid_inertia("cylinder", m["forearm"], (s.forearm_radius, fa)),
        (_capsule(s.forearm_radius, 0.0, -fa, SHIRT_LIGHT),)))
    add(p + "forearm_pronation", p + "forearm", zero, (0.0, 0.0, -sign),
        Link(p + "forearm_pronation_link"))
    # Wrist flexion turns the hand toward the palm (-y on the left); ulnar deviation turns it
    # backward (-x) on both sides because both thumbs point forward.
    add(p + "wrist_flexion", p + "forearm_pronation_link", (0.0, 0.0, -fa), (-sign, 0.0, 0.0),
        Link(p + "wrist_flexion_link"))
    hand_box = (2.4 * s.forearm_radius, 0.8 * s.forearm_radius, hand)  # breadth, thickness
    add(p + "wrist_deviation", p + "wrist_flexion_link", zero, (0.0, 1.0, 0.0), Link(
        p + "hand", m["hand"], (0.0, 0.0, -frac["hand"] * hand),
        _solid_inertia("box", m["hand"], hand_box),
        (Shape("box", hand_box, (0.0, 0.0, -hand / 2), SKIN),)))
    add(p + "grip_mount", p + "hand", (0.0, 0.0, -s.grip_offset), zero, Link(p + "grip"))
