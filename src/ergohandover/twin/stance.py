"""The worker's stance: the feet planted where they stand (``fixed``, the paper's worker), or free
to take one step toward the box before taking it (``step``).

A stepping worker moves both feet together along the floor, in the horizontal direction of the
box from the midpoint between the feet, by a whole number of quarters of one step length and
never past the box; the stance width does not change (the feet keep the twin's stance, ankle
centres a hip width apart). Everything after the step is the planted worker's, relative to the
feet where they now are: the posture, the balance task on the support rectangle under them, the
feasibility checks and the scores (REBA's legs item reads that stance: both feet bear weight).

Which step: the worker takes the candidate (no step, a quarter, ... a whole step) whose posture
costs least under the posture solver's own objective, among those in which it can take the box
(hands on the handles, the box clear of the body, balanced); ties, and locations it can take
from no candidate, keep the shorter step. The solver's objective is what the twin already
minimises for its posture (the hands' reach, the effort of the knees, hips and back, gaze,
balance, the joints' preferences), so the step is chosen by the same model as the posture, not
by the ergonomic score it is judged by.

Step length: 85.6 % of leg length, the mean step of 28 healthy younger and older men and women
walking at their preferred speed (J NeuroEng Rehabil 2012, 9:69, doi:10.1186/1743-0003-9-69,
Table 1), with the twin's hip-joint height as leg length: 0.78 m for the default worker.
"""

from __future__ import annotations

import numpy as np

from .anthropometry import BodySpec

STANCES = ("fixed", "step")
"""``fixed``: the feet stay where they are (the paper's worker); ``step``: one step toward the
box is allowed."""
STEP_PER_LEG_LENGTH = 0.856
"""Step length at preferred walking speed over leg length (J NeuroEng Rehabil 2012, 9:69,
Table 1: 85.6 %, SD 10.0 %)."""
STEP_FRACTIONS = (0.0, 0.25, 0.5, 0.75, 1.0)
"""The candidate steps, as fractions of the step length (no step first)."""


def step_length_m(body: BodySpec) -> float:
    """The longest step the worker takes toward the box [m]."""
    return STEP_PER_LEG_LENGTH * body.segments().hip_height


def step_offsets(locations: np.ndarray, body: BodySpec) -> np.ndarray:
    """(K, N, 3) the feet's displacement of each candidate step for (N, 3) box locations,
    worker frame [m]: horizontal (x, z), toward the box, never past its horizontal distance."""
    horizontal = locations * np.array([1.0, 0.0, 1.0])
    distance = np.linalg.norm(horizontal, axis=1)  # (N,)
    direction = horizontal / np.maximum(distance, 1e-12)[:, None]
    lengths = np.minimum(np.outer(STEP_FRACTIONS, np.full(len(locations), step_length_m(body))),
                         distance[None, :])  # (K, N)
    return lengths[:, :, None] * direction[None]


def after_step(locations: np.ndarray, step_m: np.ndarray) -> np.ndarray:
    """(N, 3) box locations relative to the feet after a step of ``step_m`` (N,) toward each
    box: where the twin is drawn holding it (the posture is solved there) [m]."""
    horizontal = locations * np.array([1.0, 0.0, 1.0])
    distance = np.linalg.norm(horizontal, axis=1)
    return locations - (np.asarray(step_m, float) / np.maximum(distance, 1e-12))[:, None] \
        * horizontal


def chosen_step(cost: np.ndarray, feasible: np.ndarray) -> np.ndarray:
    """(N,) the index of the candidate each location is taken with, from the candidates'
    solver objective ``cost`` and feasibility (both (K, N), no step first): the feasible one of
    lowest cost (the shorter step on ties), or no step when none is feasible."""
    ranked = np.where(feasible, cost, np.inf)
    best = np.argmin(ranked, axis=0)  # argmin takes the first (shortest) of equal costs
    return np.where(feasible.any(axis=0), best, 0)
