"""Study part `landscape`: the exhaustive sweep of the default worker (the paper's 3-hour
evaluation of every grid point), its statistics and score distribution.

Usage: python experiments/study_landscape.py [--config experiments/configs/default.json]

Writes results/landscape/: stats.csv, distribution.csv, manifest.json (with the landscape's
key), variants.csv: the same statistics on a coarser grid for each boundary (`paper-code`,
`body`) with the gaze task on and off, so that the headline numbers can be read under both, and
gaze_effect.csv: where the paper score is lowest without the gaze task, and what keeping the box
in view does to the neck, trunk, elbows and score there.
The landscapes themselves (160 MB at 3 mm) go to the landscape cache, shared with every command
and later part; a part that needs one and finds the cache empty (a fresh clone) sweeps it again.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ergohandover.io.atomic import atomic_write_csv
from ergohandover.landscape.cache import Landscape, landscape_key, landscape_path
from ergohandover.landscape.grid import Grid, parse_boundary
from ergohandover.landscape.stats import distributions, minimisers, statistics
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


def variants(part: dict, workers: int) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The landscape statistics for each boundary and gaze setting of ``part["variants"]``, and
    per boundary what the gaze task does where the paper score is lowest without it."""
    spec = part["variants"]
    frames, effects = [], []
    for boundary in spec["boundaries"]:
        grid = {"boundary": boundary, "step": spec["step"]}
        landscapes = {gaze: landscape_for(BodySpec(), grid, workers, task=TaskSpec(gaze=gaze))
                      for gaze in spec["gaze"]}
        for gaze, landscape in landscapes.items():
            stats = statistics(landscape)
            stats.insert(0, "gaze", gaze)
            stats.insert(0, "step", spec["step"])
            stats.insert(0, "boundary", boundary)
            frames.append(stats)
        if {"on", "off"} <= set(landscapes):
            effects.append({"boundary": boundary, "step": spec["step"],
                            **gaze_effect(landscapes["off"], landscapes["on"])})
    return pd.concat(frames, ignore_index=True), pd.DataFrame(effects)


def gaze_effect(off: Landscape, on: Landscape) -> dict:
    """At the gaze-off landscape's paper-score minimisers (same grid): where they are, and the
    neck, trunk, elbows and paper score there without and with the gaze task (means)."""
    cells = minimisers(off, "paper_postural")
    points = off.grid.coordinates(cells)
    out = {"points": len(cells), "paper_postural_off": int(off.arrays["paper_postural"][cells[0]]),
           **{f"{a}_{e}": f(points[:, k]) for k, a in enumerate("xyz")
              for e, f in (("min", np.min), ("max", np.max))}}
    for name, landscape in (("off", off), ("on", on)):
        for angle in ("neck_flexion", "trunk_flexion", "left_elbow_flexion"):
            out[f"{angle}_{name}"] = float(landscape.arrays[angle][cells].mean())
    scores = on.arrays["paper_postural"][cells]
    out["neck_over_20_on_share"] = float((on.arrays["neck_flexion"][cells] > 20).mean())
    out["paper_postural_on_median"] = float(np.median(scores[scores >= 0]))
    return out


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    part = part_config(config, "landscape")

    def work(folder: Path) -> dict:
        landscape = default_landscape(config, workers)
        atomic_write_csv(statistics(landscape), folder / "stats.csv")
        atomic_write_csv(distributions(landscape), folder / "distribution.csv")
        table, effect = variants(part, workers)
        atomic_write_csv(table, folder / "variants.csv")
        atomic_write_csv(effect, folder / "gaze_effect.csv")
        return {"grid": landscape.grid.describe(), "landscape_key": landscape.key,
                "sweep_seconds": landscape.meta.get("seconds")}

    run_part("landscape", results / "landscape", part, work, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
