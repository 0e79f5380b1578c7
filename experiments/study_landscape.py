"""Study part `landscape`: the exhaustive sweep of the default worker (the paper's 3-hour
evaluation of every grid point), its statistics and score distribution.

Usage: python experiments/study_landscape.py [--config experiments/configs/default.json]

Writes results/landscape/: stats.csv, distribution.csv, manifest.json (with the landscape's
key). The landscape itself (160 MB) goes to the landscape cache, shared with every command and
later part; a part that needs it and finds the cache empty (a fresh clone) sweeps it again.
"""

from __future__ import annotations

from pathlib import Path

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


def landscape_for(body: BodySpec, config: dict, workers: int, solver: str = "numpy",
                  ) -> Landscape:
    """The landscape of ``body`` on the configured boundary and step, from the landscape cache
    (swept into it when missing)."""
    task = TaskSpec()
    grid = Grid(parse_boundary(config["boundary"], body, task), config["step"])
    evaluator = Evaluator(body, task, solver)
    print(f"  {grid.describe()} for {body} ({solver} solver)")
    landscape, reused = sweep(grid, evaluator, workers=workers)
    if reused:
        print(f"  reused {landscape_path(landscape_key(evaluator, grid))}")
    return landscape


def default_landscape(config: dict, workers: int) -> Landscape:
    """The default worker's landscape of the study (the `landscape` part's)."""
    return landscape_for(BodySpec(), config["landscape"], workers)


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    part = part_config(config, "landscape")

    def work(folder: Path) -> dict:
        landscape = landscape_for(BodySpec(), part, workers)
        atomic_write_csv(statistics(landscape), folder / "stats.csv")
        atomic_write_csv(distributions(landscape), folder / "distribution.csv")
        return {"grid": landscape.grid.describe(), "landscape_key": landscape.key,
                "sweep_seconds": landscape.meta.get("seconds")}

    run_part("landscape", results / "landscape", part, work, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
