"""``evaluate(locations)``: what happens to the worker if the box is at (x, y, z)?

The one evaluation path: the sweep, the environment's online scores, the baselines, the
participants and every command call :func:`evaluate_arrays` (compact columns, any number of
worker processes) or :func:`evaluate` (the Evaluation table). For each box location (worker
frame, metres) the twin's posture is solved once, checked for feasibility, turned into the
Posture columns and scored with REBA, RULA and the paper's postural score.

Batched, deterministic and order-independent: a location's row never depends on the other
locations in the call, on the chunking, on the number of workers, or on what was evaluated
before.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..ergonomics import POSTURE_COLUMNS, SCORE_COLUMNS, Posture, ScoringSettings, score_postures
from ..errors import ConfigError
from ..executor import LocalExecutor
from .angles import posture_columns
from .anthropometry import BodySpec
from .collision import BodyProbes
from .solver import PostureSolver, SolverSettings
from .stance import chosen_step, step_offsets
from .task import TaskSpec
from .warm_start import FineLattice

SOLVERS = ("whole-body", "pybullet")
"""The twin's posture solvers: its own whole-body solver (balance, gaze, palms; compiled) and
PyBullet's IK on the hands (the ablation's)."""
TRUNK_REFERENCES = ("vertical", "pelvis")
HAND_TOLERANCE_M = 0.01
REASONS = ("hand_miss", "box_collision", "unbalanced")
"""Why a location is infeasible: a hand misses its handle by more than 1 cm; the box
intersects the torso, head or legs; the centre of mass (box included) leaves the feet.
Compact files store them as bits of a ``flags`` byte, in this order (bit 0 = hand_miss)."""
EVALUATION_COLUMNS = ("x", "y", "z", "feasible", "reason", "hand_error_m", *POSTURE_COLUMNS,
                      *SCORE_COLUMNS)
CHUNK = 4000
"""Locations per call: arrays small enough for the numpy stages, progress a few times a second,
and few enough calls that each call's fixed cost (scoring is vectorised per call) stays small."""
JOINT_PREFIX = "q_"
"""Joint-angle columns (``q_<joint>`` [rad], one per movable joint of the twin) that
:func:`evaluate_batch` adds: the solved posture, for pictures and the robot scene."""


class EvaluationError(ConfigError):
    """Locations that cannot be evaluated; the message is one line."""


@dataclass(frozen=True)
class Evaluator:
    """Everything that determines a location's row (hashable: one solver per evaluator)."""

    body: BodySpec = field(default_factory=BodySpec)
    task: TaskSpec = field(default_factory=TaskSpec)
    solver: str = "whole-body"
    settings: SolverSettings = field(default_factory=SolverSettings)
    scoring: ScoringSettings = field(default_factory=ScoringSettings)
    trunk_reference: str = "vertical"
    """Trunk flexion and side bend from vertical (the worksheets', default) or relative to the
    pelvis (the lumbar spine's own bend, as a joint-angle model would read it)."""

    def __post_init__(self):
        for name, allowed in (("solver", SOLVERS), ("trunk_reference", TRUNK_REFERENCES)):
            if getattr(self, name) not in allowed:
                raise EvaluationError(f"{name} = {getattr(self, name)!r} is not allowed (use "
                                      f"{' or '.join(repr(s) for s in allowed)})")
        if self.settings.warm_start == "fine" and self.solver != "whole-body":
            raise EvaluationError(f"warm_start = 'fine' is not allowed with solver = "
                                  f"{self.solver!r} (it interpolates the whole-body solver's "
                                  "postures: use solver 'whole-body')")
        if self.task.hands != "both" and self.solver != "whole-body":
            raise EvaluationError(f"hands = {self.task.hands!r} is not allowed with solver = "
                                  f"{self.solver!r} (its IK grips both handles: use solver "
                                  "'whole-body')")
        if self.task.stance == "step" and self.solver != "whole-body":
            raise EvaluationError(f"stance = 'step' is not allowed with solver = "
                                  f"{self.solver!r} (a step is chosen by the whole-body "
                                  "solver's objective: use solver 'whole-body')")


_SOLVERS: dict[Evaluator, PostureSolver] = {}


def posture_solver(evaluator: Evaluator, locations: np.ndarray | None = None):
    """The (cached) solver of an evaluator. Given ``locations`` (N, 3), the whole-body
    solver's kernel is compiled (or loaded from numba's disk cache) and the warm-start lattice
    nodes they need are solved here, once, so that worker processes forked afterwards share
    them."""
    if evaluator not in _SOLVERS:
        if evaluator.solver == "whole-body":
            solver = PostureSolver(evaluator.body, evaluator.task, evaluator.settings)
        else:
            from .pybullet_ik import PyBulletSolver

            solver = PyBulletSolver(evaluator.body, evaluator.task)
        _SOLVERS[evaluator] = solver
    solver = _SOLVERS[evaluator]
    if locations is not None and evaluator.solver == "whole-body":
        solver.lattice.prepare(locations)
    return solver


def evaluate_batch(evaluator: Evaluator, locations: np.ndarray,
                   columns: Iterable[str] | None = None) -> dict[str, np.ndarray]:
    """Evaluate one batch of locations in this process.

    Args:
        evaluator: body, task, solver and scoring settings.
        locations: (N, 3) box centres, worker frame [m].
        columns: the columns to return (default: all of them).

    Returns:
        Column name -> (N,) array: :data:`EVALUATION_COLUMNS` (scores as computed, also where
        infeasible), ``flags`` (uint8 bit mask of :data:`REASONS`, 0 = feasible), ``step_m``
        (how far the feet stepped toward the box [m]; 0 with the stance ``fixed``) and the
        joint angles ``q_<joint>`` [rad].
    """
    locations = check_locations(locations)
    if evaluator.task.stance == "step":
        return _stepped_batch(evaluator, locations, columns)
    return _planted_batch(evaluator, locations, columns)


def _stepped_batch(evaluator: Evaluator, locations: np.ndarray,
                   columns: Iterable[str] | None) -> dict[str, np.ndarray]:
    """:func:`evaluate_batch` of a worker who may step toward the box (:mod:`.stance`): every
    candidate step evaluated with the feet planted where it puts them, the chosen one kept;
    ``step_m`` is how far the feet moved [m]."""
    offsets = step_offsets(locations, evaluator.body)  # (K, N, 3)
    k, n = offsets.shape[:2]
    found = _planted_batch(evaluator, (locations[None] - offsets).reshape(-1, 3), None,
                           cost=True)
    rows = chosen_step(found["cost"].reshape(k, n), found["feasible"].reshape(k, n))
    take = rows * n + np.arange(n)
    out = {c: v[take] for c, v in found.items() if c != "cost"}
    out.update(x=locations[:, 0], y=locations[:, 1], z=locations[:, 2],
               step_m=np.linalg.norm(offsets[rows, np.arange(n)], axis=1))
    return out if columns is None else {c: out[c] for c in columns}


def _planted_batch(evaluator: Evaluator, locations: np.ndarray, columns: Iterable[str] | None,
                   cost: bool = False) -> dict[str, np.ndarray]:
    """:func:`evaluate_batch` with the feet where they stand (and the solver's objective as
    ``cost`` if asked)."""
    if evaluator.settings.warm_start == "fine":
        out = _fine_rows(evaluator, locations)
    else:
        out = _rows(evaluator, locations, posture_solver(evaluator).solve(locations))
    if not cost:
        del out["cost"]
    if columns is None or "reason" in columns:  # strings: only for those who ask
        out["reason"] = reason_text(out["flags"])
    return out if columns is None else {c: out[c] for c in columns}


def _rows(evaluator: Evaluator, locations: np.ndarray, solution) -> dict[str, np.ndarray]:
    """The numeric columns (and ``cost``) of solved postures: feasibility, posture, scores."""
    solver = posture_solver(evaluator)
    st = solution.state
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
    for bit, name in enumerate(REASONS):
        flags |= problems[name].astype(np.uint8) << bit
    posture = posture_columns(st, task, evaluator.trunk_reference)
    scores = score_postures(Posture(posture), evaluator.scoring)
    joints = {JOINT_PREFIX + name: solution.q[:, i]
              for i, name in enumerate(solver.model.joint_names)}
    return {"x": locations[:, 0].copy(), "y": locations[:, 1].copy(),
            "z": locations[:, 2].copy(), "feasible": flags == 0,
            "hand_error_m": solution.hand_error, "flags": flags,
            "step_m": np.zeros(len(locations)), **posture, **scores, **joints,
            "cost": solution.cost}


def _score_code(rows: dict[str, np.ndarray]) -> np.ndarray:
    """(N,) int64: the flags and, where feasible, the paper score, REBA and RULA in one number
    (two rows have the same code when a landscape stores the same flags and scores for them)."""
    feasible = rows["flags"] == 0
    code = rows["flags"].astype(np.int64)
    for shift, name in ((8, "paper_postural"), (16, "reba"), (24, "rula")):
        score = np.where(feasible, np.asarray(rows[name], dtype=np.int64) + 1, 0)
        code |= score << shift
    return code


_FINE: dict[Evaluator, FineLattice] = {}


def _fine_rows(evaluator: Evaluator, locations: np.ndarray) -> dict[str, np.ndarray]:
    """:func:`_rows` of the fine warm start (``SolverSettings.warm_start == "fine"``): each
    location interpolated from its cell of today's solves; those the cell's check leaves unsure
    (:meth:`FineLattice.unsure`) solved as today."""
    solver, settings = posture_solver(evaluator), evaluator.settings
    if evaluator not in _FINE:
        def solve_nodes(nodes):
            solution = solver.solve(nodes)
            return solution.q, _score_code(_rows(evaluator, nodes, solution))

        _FINE[evaluator] = FineLattice(settings.fine_spacing, solve_nodes)
    q, code, weight = _FINE[evaluator].corners(locations)
    start = FineLattice.interpolate(q, weight)
    out = _rows(evaluator, locations, solver.iterate(locations, start, 0))
    redo = FineLattice.unsure(q, code, _score_code(out), np.radians(settings.fine_check_deg))
    if redo.any():
        again = _rows(evaluator, locations[redo], solver.solve(locations[redo]))
        for name, values in again.items():
            out[name][redo] = values
    return out


def reason_text(flags: np.ndarray) -> np.ndarray:
    """(N,) object array: the names of the set bits of ``flags`` joined by ``;`` ("" if 0)."""
    names = [";".join(n for bit, n in enumerate(REASONS) if code >> bit & 1)
             for code in range(1 << len(REASONS))]
    return np.array(names, dtype=object)[flags]


def _batch_job(job: tuple) -> dict[str, np.ndarray]:
    return evaluate_batch(*job)


def check_locations(locations) -> np.ndarray:
    """(N, 3) finite float locations; a one-line EvaluationError otherwise."""
    locations = np.asarray(locations, dtype=float)
    if locations.ndim != 2 or locations.shape[1] != 3:
        raise EvaluationError(f"locations must have shape (N, 3), got {locations.shape}")
    if not np.isfinite(locations).all():
        row = int(np.flatnonzero(~np.isfinite(locations).all(axis=1))[0])
        raise EvaluationError(f"location row {row + 1} is not finite: {locations[row]}")
    return locations


def evaluate_stream(batches: Iterable[np.ndarray], evaluator: Evaluator | None = None,
                    columns: Iterable[str] | None = None, workers: int = 1,
                    executor: LocalExecutor | None = None) -> Iterator[dict[str, np.ndarray]]:
    """Evaluate batches of locations, in this process or over worker processes, yielding each
    batch's columns (see :func:`evaluate_batch`) in order as it finishes.

    Every batch is queued at once, so the workers never wait for the caller: a consumer that
    stores results as they arrive (the sweep's checkpoints) overlaps with the evaluation.

    Args:
        batches: (n, 3) box centres each, worker frame [m]; :data:`CHUNK` rows suit the pool.
        evaluator: body, task, solver and scoring settings (default: all defaults).
        columns: the columns to keep; only these travel back from the worker processes.
        workers: processes (1 = this process); ignored when ``executor`` is given.
        executor: an open :class:`~ergohandover.executor.LocalExecutor` to reuse.
    """
    evaluator = evaluator or Evaluator()
    columns = None if columns is None else tuple(columns)
    jobs = [(evaluator, check_locations(batch), columns) for batch in batches]
    # Its lattice nodes solved before any worker process forks.
    posture_solver(evaluator, np.vstack([job[1] for job in jobs]) if jobs else None)
    yield from (executor or LocalExecutor(workers)).map(_batch_job, jobs)


def evaluate_arrays(locations: np.ndarray, evaluator: Evaluator | None = None, workers: int = 1,
                    progress: Callable[[int], None] | None = None,
                    columns: Iterable[str] | None = None,
                    executor: LocalExecutor | None = None) -> dict[str, np.ndarray]:
    """Evaluate locations in chunks of :data:`CHUNK`, in this process or over worker processes.

    Args:
        locations: (N, 3) box centres, worker frame [m].
        evaluator: body, task, solver and scoring settings (default: all defaults).
        workers: processes (1 = this process); ignored when ``executor`` is given.
        progress: called with the number of locations finished after each chunk.
        columns: the columns to keep (see :func:`evaluate_batch`); only these travel back from
            the worker processes.
        executor: an open :class:`~ergohandover.executor.LocalExecutor` to reuse.

    Returns:
        Column name -> (N,) array, as :func:`evaluate_batch`, in the order of ``locations``.
    """
    locations = check_locations(locations)
    evaluator = evaluator or Evaluator()
    batches = [locations[a:a + CHUNK] for a in range(0, len(locations), CHUNK)]
    parts = []
    for part in evaluate_stream(batches, evaluator, columns, workers, executor):
        parts.append(part)
        if progress:
            progress(len(next(iter(part.values()))))
    if not parts:  # no locations: the columns, empty, with their dtypes
        return {c: v[:0] for c, v in evaluate_batch(evaluator, np.zeros((1, 3)), columns).items()}
    return {c: np.concatenate([p[c] for p in parts]) for c in parts[0]}


def evaluate(locations: np.ndarray, evaluator: Evaluator | None = None, workers: int = 1,
             progress: Callable[[int], None] | None = None,
             joints: bool = False) -> pd.DataFrame:
    """Evaluate box locations: posture, feasibility and every score, as a table.

    Args:
        locations: (N, 3) box centres in the worker frame [m].
        evaluator: the worker's body, the task, the solver, its settings, the scoring settings
            and the trunk-angle reference, whole (default: :class:`Evaluator`'s defaults, the
            ANSUR II 50th-percentile man and the default box).
        workers: processes to spread the chunks over (1 = this process).
        progress: called with the number of locations finished after each chunk.
        joints: also return the solved joint angles, ``q_<joint>`` columns [rad].

    Returns:
        One row per location, columns :data:`EVALUATION_COLUMNS` (the Evaluation CSV), then
        ``step_m`` for a worker who may step, then the joint columns if asked for. Score
        columns are empty (<NA>) where the location is infeasible: such a location is never
        scored as if the worker could take it.
    """
    if evaluator is not None and not isinstance(evaluator, Evaluator):
        raise EvaluationError(f"evaluator = {evaluator!r} is not an Evaluator (build one: "
                              "Evaluator(body, task, ...))")
    evaluator = evaluator or Evaluator()
    arrays = evaluate_arrays(locations, evaluator, workers, progress)
    names = [*EVALUATION_COLUMNS, *(["step_m"] if evaluator.task.stance == "step" else []),
             *(c for c in arrays if joints and c.startswith(JOINT_PREFIX))]
    frame = pd.DataFrame({c: arrays[c] for c in names})
    infeasible = ~frame["feasible"].to_numpy()
    for c in SCORE_COLUMNS:
        frame[c] = frame[c].astype("Int8")
        frame.loc[infeasible, c] = pd.NA
    frame["feasible"] = frame["feasible"].astype(np.int8)
    return frame


def joint_angles(table: pd.DataFrame) -> np.ndarray:
    """(N, nq) joint angles [rad]: the ``q_<joint>`` columns of ``evaluate(..., joints=True)``."""
    return table[[c for c in table.columns if c.startswith(JOINT_PREFIX)]].to_numpy(float)
