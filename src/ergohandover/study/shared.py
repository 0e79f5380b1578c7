"""What the study's parts share: the study's grids and the landscapes on them, through the one
landscape door and the study's engine."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from tqdm import tqdm

from ..landscape import Landscape
from ..landscape.grid import Grid, parse_boundary
from ..landscape.store import landscape_of, landscapes_of
from ..twin.evaluate import Evaluator
from .config import StudyConfig
from .engines import Engine


def grid_of(evaluator: Evaluator, boundary: str, step: float) -> Grid:
    """The grid of a named boundary (drawn for ``evaluator``'s body and task) every ``step``."""
    return Grid(parse_boundary(boundary, evaluator.body, evaluator.task), step)


def where(engine: Engine) -> dict:
    """The door's keyword arguments for the engine: the local pool of its workers (opened by
    the door, after the solver's lattice is prepared), or an executor of the engine."""
    return ({"workers": engine.workers} if engine.name == "local"
            else {"executor": engine.executor()})


def landscape(engine: Engine, evaluator: Evaluator, grid: Grid) -> Landscape:
    """One landscape, from the cache or swept on the engine."""
    print(f"  {grid.describe()} for {evaluator.body} ({evaluator.solver} solver, gaze "
          f"{evaluator.task.gaze}, stance {evaluator.task.stance})")
    found = landscape_of(evaluator, grid, **where(engine))
    print(f"  landscape {found.path}")
    return found


def landscapes(engine: Engine, evaluators: Sequence[Evaluator], grid: Grid) -> list[Landscape]:
    """Many workers' or variants' landscapes on one grid, swept side by side on the engine
    (a task per chunk of a landscape), in the order of ``evaluators``."""
    found: list[Landscape | None] = [None] * len(evaluators)
    for done in landscapes_of(evaluators, grid, **where(engine)):
        found[done.index] = done.landscape
    return found  # type: ignore[return-value]


def default_landscape(config: StudyConfig, engine: Engine) -> Landscape:
    """The default worker's landscape of the study (the `landscape` part's)."""
    evaluator = config.evaluator()
    return landscape(engine, evaluator, grid_of(evaluator, config.landscape.boundary,
                                                config.landscape.step))


@contextmanager
def ticking(bar: tqdm, every_s: float = 1.0) -> Iterator[None]:
    """Redraw ``bar`` every ``every_s`` seconds while the block runs, so that its clock moves
    while long runs hold every worker."""
    stop = threading.Event()

    def tick() -> None:
        while not stop.wait(every_s):
            bar.refresh()  # tqdm's own lock keeps this from crossing an update

    clock = threading.Thread(target=tick, daemon=True)
    clock.start()
    try:
        yield
    finally:
        stop.set()
        clock.join()


def run_jobs(engine: Engine, work: Callable[[Any], Any], jobs: Sequence, label: str,
             cost: Sequence[float] | None = None) -> list:
    """Every job through ``work`` on the engine's pool (the parent's prepared data inherited
    by its forked workers), the results in the jobs' order; the bar counts ``cost`` per job
    (default: one), so that runs that differ a thousandfold in length show honest progress."""
    cost = [1.0] * len(jobs) if cost is None else list(cost)
    results: list = [None] * len(jobs)
    # The pool forks before the bar's clock thread starts (a fork copies no threads).
    with engine.executor() as executor, \
            tqdm(total=round(sum(cost), 1), desc=label, smoothing=0,
                 bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]"
                 ) as bar, ticking(bar):
        bar.set_description_str(f"{label} (0/{len(jobs)})")
        for done, (index, result) in enumerate(executor.map_unordered(work, jobs), start=1):
            results[index] = result
            bar.set_description_str(f"{label} ({done}/{len(jobs)})", refresh=False)
            bar.update(cost[index])
    return results
