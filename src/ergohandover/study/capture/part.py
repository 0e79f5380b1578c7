"""Study part `capture`: how well each keypoint format (H36M-17, COCO-17, MediaPipe-33, ZED
BODY_34, SMPL-24) measures a worker, on the twin's own handover postures placed as each format
places its joints; and how often REBA, RULA and the paper's score come out right from them with
published angle errors added (src/ergohandover/study/capture/accuracy.py).

Writes results/capture/columns.csv (per format and angle column: the share of postures in which
it is measured and the error where it is [deg]), results/capture/scores.csv (per format, angle
error SD and score: right, holds, their 95 % intervals over postures, and the interval's mean
width) and manifest.json.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...io.atomic import atomic_write_csv
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import default_landscape
from .accuracy import column_table, score_table, twin_postures


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.capture

    def work(folder: Path) -> dict:
        found = default_landscape(config, engine)
        feasible = np.flatnonzero(found.feasible)
        rng = np.random.default_rng(part.seed)
        picked = np.sort(rng.choice(feasible, min(part.postures, feasible.size), replace=False))
        evaluator = config.evaluator()
        state, truth = twin_postures(evaluator, found.grid.coordinates(picked))
        columns = column_table(evaluator, state, truth)
        atomic_write_csv(columns, folder / "columns.csv")
        scores = score_table(evaluator, state, truth, part.angle_sds, part.draws, part.seed)
        atomic_write_csv(scores, folder / "scores.csv")
        reba = scores[scores["score"] == "reba"].set_index(["format", "angle_sd_deg"])["right"]
        print("  REBA right: " + "; ".join(
            f"{name} " + ", ".join(f"{100 * reba[(name, sd)]:.0f} %" for sd in part.angle_sds)
            for name in scores["format"].unique()) + f" at {part.angle_sds} deg")
        return {"postures": len(truth["trunk_flexion"]), "formats": int(
            scores["format"].nunique())}

    return run_part("capture", results / "capture", config.part_inputs("capture"), work,
                    force=force, engine=engine)
