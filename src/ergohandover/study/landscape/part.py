"""Study part `landscape`: the exhaustive sweep of the default worker (the paper's 3-hour
evaluation of every grid point), its statistics and score distribution.

Writes results/landscape/: stats.csv, distribution.csv, variants.csv (the same statistics on a
coarser grid for each boundary, with the gaze task on and off, so that the headline numbers can
be read under both), gaze_effect.csv (where the paper score is lowest without the gaze task, and
what keeping the box in view does to the neck, trunk, elbows and score there) and manifest.json
(with the landscape's key). The landscapes themselves (160 MB at 3 mm) go to the landscape
cache, shared with every command and later part; a part that needs one and finds the cache
empty (a fresh clone) sweeps it again.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...io.atomic import atomic_write_csv
from ...landscape import Landscape
from ...landscape.stats import distributions, minimisers, statistics
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import default_landscape, grid_of, landscapes


def variants(config: StudyConfig, engine: Engine) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The landscape statistics for each boundary and gaze setting of the variants, and per
    boundary what the gaze task does where the paper score is lowest without it."""
    spec = config.landscape.variants
    frames, effects = [], []
    for boundary in spec.boundaries:
        evaluators = [config.evaluator(gaze=gaze) for gaze in spec.gaze]
        grid = grid_of(evaluators[0], boundary, spec.step)
        found = dict(zip(spec.gaze, landscapes(engine, evaluators, grid), strict=True))
        for gaze, landscape in found.items():
            stats = statistics(landscape)
            stats.insert(0, "gaze", gaze)
            stats.insert(0, "step", spec.step)
            stats.insert(0, "boundary", boundary)
            frames.append(stats)
        if {"on", "off"} <= set(found):
            effects.append({"boundary": boundary, "step": spec.step,
                            **gaze_effect(found["off"], found["on"])})
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


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    def work(folder: Path) -> dict:
        landscape = default_landscape(config, engine)
        atomic_write_csv(statistics(landscape), folder / "stats.csv")
        atomic_write_csv(distributions(landscape), folder / "distribution.csv")
        table, effect = variants(config, engine)
        atomic_write_csv(table, folder / "variants.csv")
        atomic_write_csv(effect, folder / "gaze_effect.csv")
        return {"grid": landscape.grid.describe(), "landscape_key": landscape.key,
                "sweep_seconds": landscape.meta.get("seconds")}

    return run_part("landscape", results / "landscape", config.part_inputs("landscape"), work,
                    force=force, engine=engine)
