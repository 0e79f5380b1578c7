"""The twin's postures over much of its joint ranges, for the capture layer's round trips."""

from __future__ import annotations

import numpy as np

from ergohandover.capture.formats import SIDES
from ergohandover.twin.angles import posture_columns
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.kinematics import KinematicModel, KinematicState
from ergohandover.twin.skeleton import build_skeleton
from ergohandover.twin.task import TaskSpec


def random_twin_postures(n: int, seed: int, body: BodySpec | None = None
                         ) -> tuple[BodySpec, KinematicState, dict[str, np.ndarray]]:
    """N postures over 60 % of the twin's joint ranges (the upper arms within 80° of
    abduction, the Euler branch the capture reads): the body, their forward kinematics and the
    twin's own Posture columns (the default task's box)."""
    body = body or BodySpec()
    model = KinematicModel(build_skeleton(body))
    rng = np.random.default_rng(seed)
    q = rng.uniform(0.6 * model.lower, 0.6 * model.upper, (n, model.nq))
    for side in SIDES:
        q[:, model.index(f"{side}_shoulder_abduction")] = rng.uniform(-0.5, 1.4, n)
    state = model.forward(q)
    return body, state, posture_columns(state, TaskSpec())
