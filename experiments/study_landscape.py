"""Study part `landscape`: the exhaustive sweep of the default worker (the paper's 3-hour
evaluation of every grid point), its statistics and score distribution.

Usage: python experiments/study_landscape.py [--config experiments/configs/default.json]

Writes results/landscape/: landscape.npz (not committed: 105 MB, rebuilt in ~5 min),
stats.csv, distribution.csv, manifest.json.
"""

from __future__ import annotations

from pathlib import Path

from ergohandover.io.atomic import atomic_write_csv
from ergohandover.landscape.grid import Grid, parse_boundary
from ergohandover.landscape.stats import distributions, statistics
from ergohandover.landscape.sweep import Landscape, sweep
from ergohandover.study.parts import part_config, run_part, study_main
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import TaskSpec

ROOT = Path(__file__).resolve().parents[1]


def landscape_for(body: BodySpec, config: dict, output: Path, workers: int) -> Landscape:
    """The (cached) landscape of ``body`` on the configured boundary and step."""
    task = TaskSpec()
    grid = Grid(parse_boundary(config["boundary"], body, task), config["step"])
    print(f"  {grid.describe()} for {body}")
    landscape, reused = sweep(grid, Evaluator(body, task), output, workers=workers)
    if reused:
        print(f"  reused {output}")
    return landscape


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    part = part_config(config, "landscape")

    def work(folder: Path) -> dict:
        landscape = landscape_for(BodySpec(), part, folder / "landscape.npz", workers)
        atomic_write_csv(statistics(landscape), folder / "stats.csv")
        atomic_write_csv(distributions(landscape), folder / "distribution.csv")
        return {"grid": landscape.grid.describe(), "landscape_key": landscape.key,
                "sweep_seconds": landscape.meta.get("seconds")}

    run_part("landscape", results / "landscape", part, work, force=force,
             required_files=("landscape.npz",))


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
