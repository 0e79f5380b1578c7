"""Study part `manikins`: the standard boundary manikins at every headline location.

The four manikins of workplace design (the 5th-percentile woman, the 50th woman, the 50th man,
the 95th man; :mod:`ergohandover.workload.manikins`) each take the box at every headline
location of the default worker (the robustness part's: the nominal and robust optima, the
largest margin, the learned location, the practice rule, the one-size locations and each
start's shortest-distance location). For each: feasibility, REBA, RULA, the paper's score,
OWAS, the revised NIOSH lifting equation for the study's lifting task and the static back
load (docs/workload.md).

Writes results/manikins/:
  manikins.csv   one row per manikin and location: its body, the location, every score and
                 every workload column (empty where the manikin cannot take the box there)
  manifest.json
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ...io.atomic import atomic_write_csv
from ...twin.evaluate import Evaluator, evaluate
from ...workload import Levers, workload_table
from ...workload.manikins import MANIKINS, manikin
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..robustness.recorded import headline_locations

SCORES = ("reba", "rula", "paper_postural")


def manikin_table(config: StudyConfig, named: pd.DataFrame) -> pd.DataFrame:
    """Every manikin at every named location: scores and workload columns."""
    lift = config.manikins.lift()
    points = named[["x", "y", "z"]].to_numpy(float)
    frames = []
    for name in MANIKINS:
        body = manikin(name)
        table = evaluate(points, Evaluator(body, config.task()))
        work = workload_table(table, Levers.of(body), lift,
                              rows=table["feasible"].to_numpy(dtype=bool))
        frames.append(pd.concat([
            pd.DataFrame({"manikin": name, "stature_m": body.stature_m,
                          "mass_kg": body.mass_kg, "sex": body.sex,
                          "location": named["location"]}),
            table[["x", "y", "z", "feasible", "reason", *SCORES]], work], axis=1))
    return pd.concat(frames, ignore_index=True)


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:

    def work(folder: Path) -> dict:
        named = headline_locations(results)
        print(f"  {len(MANIKINS)} manikins at {len(named)} headline locations")
        table = manikin_table(config, named)
        atomic_write_csv(table, folder / "manikins.csv")
        return {"manikins": list(MANIKINS), "locations": len(named)}

    return run_part("manikins", results / "manikins", config.part_inputs("manikins"), work,
                    seeds={}, force=force, engine=engine)
