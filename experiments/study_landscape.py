"""Study part `landscape`: the exhaustive sweep of the default worker (the paper's 3-hour
evaluation of every grid point), its statistics and score distribution.

Usage: python experiments/study_landscape.py [--config experiments/configs/default.json]

Writes results/landscape/: stats.csv, distribution.csv, manifest.json (with the landscape's
key), and variants.csv: the same statistics on a coarser grid for each boundary (`paper-code`,
`body`) with the gaze task on and off, so that the headline numbers can be read under both.
The landscapes themselves (160 MB at 3 mm) go to the landscape cache, shared with every command
and later part; a part that needs one and finds the cache empty (a fresh clone) sweeps it again.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ergohandover.io.atomic import atomic_write_csv
from ergohandover.landscape.cache import Landscape, landscape_key, landscape_path
from ergohandover.landscape.grid import Grid, parse_boundary
from ergohandover.landscape.stats import distributions, statistics
from ergohandover.landscape.sweep import sweep
from ergohandover.study.parts import part_config, run_part, study_main
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import TaskSpec

ROOT = Path(__file__).resolve().parents[1]


def study_task(config: dict) -> TaskSpec:
    """The study's task: the default box, with the landscape section's ``gaze`` (on|off)."""
    return TaskSpec(gaze=config["landscape"].get("gaze", "on"))


def landscape_of(evaluator: Evaluator, config: dict, workers: int) -> Landscape:
    """The landscape of ``evaluator`` on the configured boundary and step (``config``: a
    section with ``boundary`` and ``step``), from the landscape cache (swept into it when
    missing)."""
    grid = Grid(parse_boundary(config["boundary"], evaluator.body, evaluator.task),
                config["step"])
    print(f"  {grid.describe()} for {evaluator.body} ({evaluator.solver} solver, "
          f"gaze {evaluator.task.gaze})")
    landscape, reused = sweep(grid, evaluator, workers=workers)
    if reused:
        print(f"  reused {landscape_path(landscape_key(evaluator, grid))}")
    return landscape


def landscape_for(body: BodySpec, config: dict, workers: int, solver: str = "numpy",
                  task: TaskSpec | None = None) -> Landscape:
    """:func:`landscape_of` the default evaluator with this body, solver and task."""
    return landscape_of(Evaluator(body, task or TaskSpec(), solver), config, workers)


def default_landscape(config: dict, workers: int) -> Landscape:
    """The default worker's landscape of the study (the `landscape` part's)."""
    return landscape_for(BodySpec(), config["landscape"], workers, task=study_task(config))


def variants(part: dict, workers: int) -> pd.DataFrame:
    """The landscape statistics for each boundary and gaze setting of ``part["variants"]``."""
    spec = part["variants"]
    frames = []
    for boundary in spec["boundaries"]:
        for gaze in spec["gaze"]:
            grid = {"boundary": boundary, "step": spec["step"]}
            stats = statistics(landscape_for(BodySpec(), grid, workers,
                                             task=TaskSpec(gaze=gaze)))
            stats.insert(0, "gaze", gaze)
            stats.insert(0, "step", spec["step"])
            stats.insert(0, "boundary", boundary)
            frames.append(stats)
    return pd.concat(frames, ignore_index=True)


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    part = part_config(config, "landscape")

    def work(folder: Path) -> dict:
        landscape = default_landscape(config, workers)
        atomic_write_csv(statistics(landscape), folder / "stats.csv")
        atomic_write_csv(distributions(landscape), folder / "distribution.csv")
        atomic_write_csv(variants(part, workers), folder / "variants.csv")
        return {"grid": landscape.grid.describe(), "landscape_key": landscape.key,
                "sweep_seconds": landscape.meta.get("seconds")}

    run_part("landscape", results / "landscape", part, work, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
