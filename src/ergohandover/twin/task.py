"""The handover task: the box, its handles, and the boundary in which it may be handed over.

All positions are in the worker frame (x right, y up, z forward; metres). A location is the
centre of the box; the handles sit on its left and right faces, at the box centre's height and
depth, ``handle_span`` apart.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..ranges import check_ranges, ranged
from .anthropometry import BodySpec
from .stance import STANCES

HANDS = ("both", "right", "left")
"""Which hand takes the object: both handles, or the right or left hand alone."""


class TaskSpecError(ConfigError):
    """A task setting outside its valid range; the message is one line."""


@dataclass(frozen=True)
class TaskSpec:
    """A box with two side handles, handed to a standing worker.

    Defaults describe a small construction box (fixings, a tool case): 0.36 m wide so that the
    handles, 0.40 m apart, meet the hands at about shoulder width; 0.25 m high and 0.30 m deep;
    6 kg, inside one-person lifting guidance and in REBA's 5–10 kg load band. Moulded handles
    with a power grip give coupling 0 ("good"). Holding the box for the handover is neither
    static beyond a minute nor repeated, so activity is 0.

    ``gaze``: whether the worker keeps the box in view. "on" (the default) adds the solver's
    gaze task: the line of sight may turn only within the eyes' comfortable cone of the box
    centre, beyond it the head and trunk turn. "off" ignores where the worker looks.

    ``stance``: "fixed" (the default, the paper's worker) keeps the feet where they stand;
    "step" lets the worker step toward the box first (:mod:`.stance`).

    ``hands``: "both" (the default) grips the two handles; "right" or "left" takes the object
    in that hand alone, its grip point at the object's centre (a bottle or a baton held round
    its middle, the palm facing the midline) and the whole mass in that hand, while the other
    arm holds only its own weight. :data:`OBJECTS` names a baton and a bottle beside the box.
    """

    box_width: float = ranged(0.36, "box width, side to side [m]", 0.02, 1.00)
    box_height: float = ranged(0.25, "box height [m]", 0.02, 1.00)
    box_depth: float = ranged(0.30, "box depth, front to back [m]", 0.02, 1.00)
    box_mass_kg: float = ranged(6.0, "box mass [kg]", 0.0, 25.0)
    handle_span: float = ranged(0.40, "distance between the two handle grips [m]", 0.15, 1.10)
    coupling: int = ranged(0, "REBA coupling of the handles: 0 good ... 3 unacceptable", 0, 3)
    activity: int = ranged(0, "REBA activity score 0-3", 0, 3)
    clearance: float = ranged(0.02, "gap kept between the box and the torso [m]", 0.0, 0.20)
    gaze: str = ranged("on", "keep the box in view ('on') or ignore where the worker looks "
                       "('off')", choices=("on", "off"))
    stance: str = ranged("fixed", "the feet stay planted ('fixed', the paper's worker) or may "
                         "take one step toward the box ('step')", choices=STANCES)
    hands: str = ranged("both", "which hand takes the object: both handles ('both') or one "
                        "hand round the object's centre ('right', 'left')", choices=HANDS)

    def __post_init__(self):
        check_ranges(self, TaskSpecError)
        if self.hands == "both" and self.handle_span < self.box_width:
            raise TaskSpecError(f"handle_span = {self.handle_span!r} is outside the valid range: "
                                f"at least box_width = {self.box_width!r}")

    @classmethod
    def holding(cls, name: str, **fields) -> TaskSpec:
        """The task with object ``name`` of :data:`OBJECTS` (its size and mass), ``fields``
        overriding."""
        if name not in OBJECTS:
            raise TaskSpecError(f"object = {name!r} is not allowed (use {', '.join(OBJECTS)})")
        return cls(**{**OBJECTS[name], **fields})

    def grip_shares(self) -> tuple[float, float]:
        """The share of the object's weight in the left and the right hand; a hand with no
        share has no grip task either."""
        return {"both": (0.5, 0.5), "left": (1.0, 0.0), "right": (0.0, 1.0)}[self.hands]

    def handles(self, locations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Left and right grip points for box centres ``locations`` (N, 3) [m]: the handles,
        or with one hand the object's centre for both (only the taking hand reaches it)."""
        if self.hands != "both":
            return locations.copy(), locations.copy()
        offset = np.array([self.handle_span / 2.0, 0.0, 0.0])
        return locations - offset, locations + offset  # left is -x in the worker frame


OBJECTS: dict[str, dict[str, float]] = {
    "box": {},
    # A relay baton (Handovers@RPL's object): about 0.30 m long, 0.04 m across, 0.1 kg.
    "baton": {"box_width": 0.04, "box_height": 0.30, "box_depth": 0.04, "box_mass_kg": 0.1},
    # A filled half-litre bottle: 0.07 m across, 0.22 m tall, 0.55 kg.
    "bottle": {"box_width": 0.07, "box_height": 0.22, "box_depth": 0.07,
               "box_mass_kg": 0.55},
}
"""Objects the task can hold, as TaskSpec fields: the study's box (the defaults) and two small
objects handed over in one hand, sized as common ones are."""


@dataclass(frozen=True)
class Boundary:
    """An axis-aligned box of candidate locations, in the worker frame [m]."""

    x: tuple[float, float]
    y: tuple[float, float]
    z: tuple[float, float]
    name: str = "explicit"

    def __post_init__(self):
        for axis in ("x", "y", "z"):
            lo, hi = getattr(self, axis)
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise TaskSpecError(f"boundary {axis} = {lo:g}..{hi:g} is empty or inverted "
                                    "(need finite lo < hi)")

    @property
    def lower(self) -> np.ndarray:
        return np.array([self.x[0], self.y[0], self.z[0]])

    @property
    def upper(self) -> np.ndarray:
        return np.array([self.x[1], self.y[1], self.z[1]])

    def sample(self, n: int, rng: np.random.Generator) -> np.ndarray:
        """N uniform random locations inside the boundary, (N, 3)."""
        return rng.uniform(self.lower, self.upper, size=(n, 3))

    @classmethod
    def paper_code(cls) -> Boundary:
        """The published code's numbers: x ±0.20, y 0.72-1.44, z 0.30-0.60 m."""
        return cls((-0.20, 0.20), (0.72, 1.44), (0.30, 0.60), name="paper-code")

    @classmethod
    def from_body(cls, body: BodySpec, task: TaskSpec) -> Boundary:
        """The paper's text: x ± half shoulder width; y knee height to the top of the head;
        z from where the box first clears the torso to full arm reach."""
        seg = body.segments()
        half = seg.shoulder_width / 2.0
        clear = seg.trunk_depth / 2.0 + task.box_depth / 2.0 + task.clearance
        reach = seg.upper_arm_length + seg.forearm_length + seg.grip_offset
        return cls((-half, half), (seg.knee_height, body.stature_m), (clear, reach), name="body")
