"""What the study's parts share: the study's grids and the landscapes on them, through the one
landscape door and the study's engine."""

from __future__ import annotations

from collections.abc import Sequence

from ...landscape import Landscape
from ...landscape.grid import Grid, parse_boundary
from ...landscape.store import landscape_of, landscapes_of
from ...twin.evaluate import Evaluator
from ..config import StudyConfig
from ..engines import Engine


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
