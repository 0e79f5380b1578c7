"""What every search shares: the budget, the best-so-far tracker, the :class:`Record` of what a
search saw, and its files (trace CSV, best-location CSV, optional Q-table or network,
manifest.json)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..errors import ConfigError
from ..io.atomic import atomic_write, atomic_write_csv
from ..io.manifest import write_manifest
from ..landscape.stats import most_symmetric

TRACE_COLUMNS = ("time_s", "step", "best_score", "best_x", "best_y", "best_z")
BLOCK = 4096
"""Steps between clock checks, progress updates and refills of pre-drawn random numbers: few
enough that a time cap is kept closely, many enough that the checks cost the loop nothing."""

Progress = Callable[[int, float], None]
"""Called as ``progress(spent, elapsed_s)``: every :data:`BLOCK` steps, every evaluation."""


UNITS = ("steps", "evaluations")
"""What a search's budget counts. ``steps``: every score an agent reads (an env step, or one of
random draws), repeats included: the learners' unit. ``evaluations``: distinct cells
scored, a repeat answered from memory for nothing (:class:`~.protocol.Evaluations`): the unit
of a real handover."""


@dataclass(frozen=True)
class Budget:
    """When a search stops: at a wall-clock cap, a cap of steps or of evaluations (one unit of
    :data:`UNITS`, or none), or at a score reached, whichever comes first.

    Args:
        seconds: wall-clock cap [s].
        steps: cap of env steps (or score draws).
        evaluations: cap of distinct cells scored.
        stop_score: stop as soon as a score at or below this is seen (benchmarks of
            time-to-minimum); None runs to the cap, as the paper does.
        stop_cells: (grid.size,) bool: stop only at one of these cells (at or below
            ``stop_score``, if given): a target that is a subset of the cells at the minimum.
    """

    seconds: float | None = None
    steps: int | None = None
    evaluations: int | None = None
    stop_score: float | None = None
    stop_cells: np.ndarray | None = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        if self.seconds is None and self.steps is None and self.evaluations is None:
            raise ConfigError("a budget needs a time cap, a step cap or an evaluation cap")
        if self.steps is not None and self.evaluations is not None:
            raise ConfigError("a budget counts steps or evaluations, not both")
        if self.seconds is not None and not (math.isfinite(self.seconds) and self.seconds > 0):
            raise ConfigError(f"seconds = {self.seconds!r} is outside the valid range (> 0 s)")
        for name in UNITS:
            value = getattr(self, name)
            if value is not None and value < 1:
                raise ConfigError(f"{name} = {value!r} is outside the valid range (at least 1)")

    @classmethod
    def of(cls, unit: str, count: int | None, seconds: float | None = None,
           **stop) -> Budget:
        """A budget of ``count`` in ``unit`` (one of :data:`UNITS`) and/or ``seconds``."""
        if unit not in UNITS:
            raise ConfigError(f"unit = {unit!r} is not allowed (use {' or '.join(UNITS)})")
        return cls(seconds, **{unit: count}, **stop)

    @property
    def step_limit(self) -> int | float:
        return math.inf if self.steps is None else self.steps

    @property
    def time_limit(self) -> float:
        return math.inf if self.seconds is None else self.seconds


class Tracker:
    """The lowest score seen, every distinct cell where it was seen, and a time-stamped trace.

    Callers offer a score only when ``score <= best`` (the comparison stays in the agents'
    loops, where it is cheap); a strictly lower score starts a new set of cells and adds a trace
    row.

    Args:
        location: flat cell -> (x, y, z) [m].
        stop_score: the score at or below which the search stops (the budget's; None: never,
            unless ``stop_cells`` is given).
        stop_cells: (grid.size,) bool: stop only at one of these cells (the budget's).
    """

    def __init__(self, location: Callable[[int], tuple[float, float, float]],
                 stop_score: float | None = None, stop_cells: np.ndarray | None = None):
        self.location = location
        self.stop_cells = stop_cells
        never = stop_score is None and stop_cells is None
        self.stop_score = -math.inf if never else math.inf if stop_score is None else stop_score
        self.hit = False
        self.best = math.inf
        self.cells: dict[int, int] = {}  # cell at the best score -> step first seen there
        self.rows: list[tuple] = []
        self.start = time.perf_counter()
        self.stopped: float | None = None

    @classmethod
    def of(cls, location, budget: Budget) -> Tracker:
        """A tracker that stops where ``budget`` says."""
        return cls(location, budget.stop_score, budget.stop_cells)

    def offer(self, step: int, score: float, cell: int) -> bool:
        """Record ``score`` seen at ``cell`` at ``step``; True when it reaches the stop score
        (the agent then stops)."""
        if score == math.inf:  # an infeasible cell is never a best location
            return False
        if score < self.best:
            self.best = score
            self.cells = {cell: step}
            self.rows.append((time.perf_counter() - self.start, step, score,
                              *self.location(cell)))
        elif cell not in self.cells:
            self.cells[cell] = step
        if score <= self.stop_score and (self.stop_cells is None or self.stop_cells[cell]):
            self.hit = True
        return self.hit

    @property
    def reached(self) -> bool:
        """Whether a stop cell (or score) has been seen: the search stops."""
        return self.hit

    def elapsed(self) -> float:
        """Seconds since the run started (until :meth:`stop`)."""
        if self.stopped is not None:
            return self.stopped
        return time.perf_counter() - self.start

    def stop(self) -> None:
        """Freeze the clock: the search is over (what follows is bookkeeping)."""
        self.stopped = self.elapsed()

    def finish(self, searcher: str, steps: int, budget: Budget, info: dict | None = None,
               **policy) -> Record:
        """Close a run counted in steps: why it stopped, from the tracker and ``budget``."""
        if self.reached:
            stopped_by = "stop_score"
        else:
            stopped_by = "step_cap" if steps >= budget.step_limit else "time_cap"
        return self.record(searcher, steps, stopped_by, "steps", info, **policy)

    def record(self, searcher: str, spent: int, stopped_by: str, unit: str = "steps",
               info: dict | None = None, **seen) -> Record:
        """Close the run: the final trace row, what was spent and why it stopped; ``seen``:
        the cells and scores evaluated, or what a learner leaves to roll out (``q_table``,
        ``model``)."""
        self.stop()
        elapsed = self.elapsed()
        last = self.rows[-1][2:] if self.rows else (math.inf, math.nan, math.nan, math.nan)
        rows = [*self.rows, (elapsed, spent, *last)]
        # Grid coordinates are lower + i * step: round away the float noise (to 1 µm, 1 µs).
        trace = pd.DataFrame(rows, columns=TRACE_COLUMNS).round(6)
        return Record(searcher, self.best, self.cells, trace, spent, elapsed, stopped_by, unit,
                      info=info or {}, **seen)


@dataclass
class Record:
    """What one search saw: the one result of every searcher and agent, whoever ran it (the
    study, ``train``, ``personalise``).

    Attributes:
        searcher: the registry's name.
        best_score: lowest score seen (``inf`` if only infeasible cells were seen).
        best_cells: flat cell -> step first seen, for every cell at ``best_score``, in the
            order found.
        trace: one row per improvement and a last row at the end (:data:`TRACE_COLUMNS`; its
            ``step`` counts ``unit``).
        steps: what was spent, in ``unit``.
        elapsed_s: wall time [s].
        stopped_by: ``time_cap``, ``step_cap``, ``evaluation_cap``, ``stop_score``, ``grid``
            (every cell evaluated) or ``ask_cap`` (the searcher kept proposing known cells).
        unit: ``steps`` or ``evaluations``.
        cells: the distinct cells evaluated, in order, when the budget counted evaluations (a
            run counted in steps, millions of them, keeps only :attr:`best_cells`).
        scores: their scores (``inf``: infeasible).
        info: the searcher's own figures (episodes, final temperature, asks, ...).
        settings: the searcher's own configuration (hyperparameters), if it has one.
        q_table: (visited states (n,), Q-values (n, 6)) for the tabular learner.
        model: the trained network (an SB3 model) for DQN and SAC.
    """

    searcher: str
    best_score: float
    best_cells: dict[int, int]
    trace: pd.DataFrame
    steps: int
    elapsed_s: float
    stopped_by: str
    unit: str = "steps"
    cells: list[int] = field(default_factory=list)
    scores: list[float] = field(default_factory=list)
    info: dict = field(default_factory=dict)
    settings: dict | None = None
    q_table: tuple[np.ndarray, np.ndarray] | None = None
    model: Any = None

    @property
    def first_reached(self) -> tuple[float, int]:
        """(time [s], step) at which ``best_score`` was first seen."""
        row = self.trace.iloc[-2] if len(self.trace) > 1 else self.trace.iloc[-1]
        return float(row["time_s"]), int(row["step"])

    @property
    def best(self) -> tuple[int, float] | None:
        """The first cell found at the lowest score, and that score (None: nothing feasible)."""
        if not self.best_cells:
            return None
        return next(iter(self.best_cells)), self.best_score

    def reached_at(self, threshold: float) -> int | None:
        """The step (in :attr:`unit`) of the first score at or below ``threshold``; None if
        none was. A first such score is always a new best, so the trace holds it."""
        steps = self.trace["step"].to_numpy()[:-1]
        hits = np.flatnonzero(self.trace["best_score"].to_numpy()[:-1] <= threshold)
        return int(steps[hits[0]]) if hits.size else None


def best_locations(result: Record, location) -> pd.DataFrame:
    """The cells at the best score, the most symmetric first, then by |x|, y, z.

    Args:
        result: a run.
        location: flat cell -> (x, y, z) [m].
    """
    cells = list(result.best_cells)
    if not cells:
        return pd.DataFrame(columns=["x", "y", "z", "score", "cell", "first_step"])
    points = np.array([location(c) for c in cells])  # (n, 3)
    first = most_symmetric(points)
    order = sorted(range(len(cells)), key=lambda i: (i != first, abs(points[i, 0]),
                                                     points[i, 1], points[i, 2]))
    points = points.round(6)  # grid coordinates are lower + i * step: float noise below 1 µm
    return pd.DataFrame({
        "x": points[order, 0], "y": points[order, 1], "z": points[order, 2],
        "score": result.best_score, "cell": [cells[i] for i in order],
        "first_step": [result.best_cells[cells[i]] for i in order]})


def write_record(result: Record, location, output: Path, config: dict, seeds: dict,
                 extra: dict | None = None) -> list[Path]:
    """Write ``trace.csv``, ``best_locations.csv``, ``q_table.npz`` or the network
    (``dqn_model.zip``, ``sac_model.zip``; if any) and ``manifest.json`` into ``output``
    (created if needed), each atomically.

    Args:
        result: the run.
        location: flat cell -> (x, y, z) [m].
        output: the result directory.
        config: the resolved configuration (goes into the manifest).
        seeds: every seed, by concern.
        extra: more figures for the manifest.
    """
    output.mkdir(parents=True, exist_ok=True)
    paths = [atomic_write_csv(result.trace, output / "trace.csv"),
             atomic_write_csv(best_locations(result, location), output / "best_locations.csv")]
    if result.q_table is not None:
        states, values = result.q_table
        paths.append(atomic_write(
            output / "q_table.npz",
            lambda h: np.savez_compressed(h, states=states, q=values), binary=True))
    if result.model is not None:
        paths.append(atomic_write(output / f"{result.searcher}_model.zip", result.model.save,
                                  binary=True))
    time_s, step = result.first_reached
    best = None if math.isinf(result.best_score) else result.best_score  # JSON has no inf
    summary = {"agent": result.searcher, "best_score": best,
               "n_best_locations": len(result.best_cells), "first_reached_s": round(time_s, 4),
               "first_reached_step": step, "steps": result.steps,
               "stopped_by": result.stopped_by, **result.info, **(extra or {})}
    paths.append(write_manifest(output, config=config, seeds=seeds,
                                wall_time_s=result.elapsed_s, extra={"summary": summary}))
    return paths
