"""``evaluate(locations)``: what happens to the worker if the box is at (x, y, z)?

The one function every sweep, environment, baseline and experiment calls. For each box location
(worker frame, metres) the twin's posture is solved, checked for feasibility, turned into the
Posture columns and scored with REBA, RULA and the paper's postural score.

Batched, deterministic and order-independent: a location's row never depends on the other
locations in the call, on the chunking, or on what was evaluated before.
"""

from __future__ import annotations

import multiprocessing
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..ergonomics import POSTURE_COLUMNS, SCORE_COLUMNS, Posture, ScoringSettings, score_postures
from .angles import posture_columns
from .anthropometry import BodySpec
from .collision import BodyProbes
from .solver import PostureSolver, SolverSettings
from .task import TaskSpec

SOLVERS = ("numpy", "pybullet")
HAND_TOLERANCE_M = 0.01
REASONS = ("hand_miss", "box_collision", "unbalanced")
"""Why a location is infeasible: a hand misses its handle by more than 1 cm; the box
intersects the torso, head or legs; the centre of mass (box included) leaves the feet.
Compact files store them as bits of a ``flags`` byte, in this order (bit 0 = hand_miss)."""
EVALUATION_COLUMNS = ("x", "y", "z", "feasible", "reason", "hand_error_m", *POSTURE_COLUMNS,
                      *SCORE_COLUMNS)
CHUNK = 500  # locations per solver call: small enough to stay in cache


class EvaluationError(ValueError):
    """Locations that cannot be evaluated; the message is one line."""


@dataclass(frozen=True)
class Evaluator:
    """Everything that determines a location's row (hashable: one solver per evaluator)."""

    body: BodySpec = field(default_factory=BodySpec)
    task: TaskSpec = field(default_factory=TaskSpec)
    solver: str = "numpy"
    settings: SolverSettings = field(default_factory=SolverSettings)
    scoring: ScoringSettings = field(default_factory=ScoringSettings)

    def __post_init__(self):
        if self.solver not in SOLVERS:
            raise EvaluationError(f"solver = {self.solver!r} is not allowed (use "
                                  f"{' or '.join(repr(s) for s in SOLVERS)})")


_SOLVERS: dict[Evaluator, PostureSolver] = {}


def posture_solver(evaluator: Evaluator):
    """The (cached) solver of an evaluator; the numpy solver's lattice is solved here."""
    if evaluator not in _SOLVERS:
        if evaluator.solver == "numpy":
            solver = PostureSolver(evaluator.body, evaluator.task, evaluator.settings)
            solver.lattice  # noqa: B018  (solve it once, before any worker process forks)
        else:
            from .pybullet_ik import PyBulletSolver

            solver = PyBulletSolver(evaluator.body, evaluator.task)
        _SOLVERS[evaluator] = solver
    return _SOLVERS[evaluator]


def _evaluate_chunk(evaluator: Evaluator, locations: np.ndarray) -> dict[str, np.ndarray]:
    solver = posture_solver(evaluator)
    solution = solver.solve(locations)
    st = solution.state
    columns = posture_columns(st, evaluator.task)
    task = evaluator.task
    centre = solver.targets(locations).box
    half = np.array([task.box_depth, task.box_width, task.box_height]) / 2.0  # world x, y, z
    x0, x1, y0, y1 = solver.support
    com = solution.com
    problems = {
        "hand_miss": solution.hand_error > HAND_TOLERANCE_M,
        "box_collision": BodyProbes.of(solver.model.skeleton).box_hits_body(st, centre, half),
        "unbalanced": ~((com[:, 0] >= x0) & (com[:, 0] <= x1) & (com[:, 1] >= y0)
                        & (com[:, 1] <= y1)),
    }
    flags = np.zeros(len(locations), dtype=np.uint8)
    reason = np.full(len(locations), "", dtype=object)
    for bit, name in enumerate(REASONS):
        flags |= problems[name].astype(np.uint8) << bit
        reason = np.where(problems[name], np.where(reason == "", name, reason + ";" + name),
                          reason)
    scores = score_postures(Posture(columns), evaluator.scoring)
    return {"x": locations[:, 0], "y": locations[:, 1], "z": locations[:, 2],
            "feasible": flags == 0, "reason": reason, "hand_error_m": solution.hand_error,
            "flags": flags, **columns, **scores}


def _run(args):
    return _evaluate_chunk(*args)


def evaluate(locations: np.ndarray, body: BodySpec | None = None, task: TaskSpec | None = None,
             solver: str = "numpy", settings: SolverSettings | None = None,
             scoring: ScoringSettings | None = None, workers: int = 1,
             progress: Callable[[int], None] | None = None) -> pd.DataFrame:
    """Evaluate box locations: posture, feasibility and every score.

    Args:
        locations: (N, 3) box centres in the worker frame [m].
        body: the worker (default: ANSUR II 50th-percentile man).
        task: the box and handles (default: :class:`TaskSpec`).
        solver: ``numpy`` (the whole-body solver) or ``pybullet`` (PyBullet's IK on the hands).
        settings: posture-solver weights.
        scoring: REBA/RULA settings.
        workers: processes to spread the chunks over (1 = this process).
        progress: called with the number of locations finished after each chunk.

    Returns:
        One row per location, columns :data:`EVALUATION_COLUMNS` (DESIGN.md's Evaluation CSV).
        Score columns are empty (<NA>) where the location is infeasible: such a location is
        never scored as if the worker could take it.
    """
    locations = np.asarray(locations, dtype=float)
    if locations.ndim != 2 or locations.shape[1] != 3:
        raise EvaluationError(f"locations must have shape (N, 3), got {locations.shape}")
    if not np.isfinite(locations).all():
        row = int(np.flatnonzero(~np.isfinite(locations).all(axis=1))[0])
        raise EvaluationError(f"location row {row + 1} is not finite: {locations[row]}")
    evaluator = Evaluator(body or BodySpec(), task or TaskSpec(), solver,
                          settings or SolverSettings(), scoring or ScoringSettings())
    posture_solver(evaluator)
    jobs = [(evaluator, locations[a:a + CHUNK]) for a in range(0, len(locations), CHUNK)]
    parts = []
    if workers > 1 and len(jobs) > 1:
        with multiprocessing.get_context("fork").Pool(workers) as pool:
            for part in pool.imap(_run, jobs):
                parts.append(part)
                if progress:
                    progress(len(part["x"]))
    else:
        for job in jobs:
            parts.append(_run(job))
            if progress:
                progress(len(parts[-1]["x"]))
    if not parts:
        return pd.DataFrame({c: [] for c in EVALUATION_COLUMNS})
    frame = pd.DataFrame({c: np.concatenate([p[c] for p in parts]) for c in EVALUATION_COLUMNS})
    infeasible = ~frame["feasible"].to_numpy()
    for c in SCORE_COLUMNS:
        frame[c] = frame[c].astype("Int8")
        frame.loc[infeasible, c] = pd.NA
    frame["feasible"] = frame["feasible"].astype(np.int8)
    return frame
