"""Study part `stance`: does "optimised beats shortest distance" survive a worker who can step?

The paper's worker keeps its feet planted, so a shortest-distance location at full reach (0.60 m
in front) is taken by reaching out, where a person would step toward the robot. Here every
headline location is scored twice, for the planted worker and for one who may take a step
toward the box (:mod:`ergohandover.twin.stance`): the default worker's optimised location (the
learner's, as the baselines part serves it) and each of the paper's starts' shortest-distance
locations; the participants' own and default optimised locations and their two starts'
shortest-distance ones; and the stepping worker's own optimum, from its landscape. The default
worker's comparisons are repeated under posture-measurement error (the robustness part's
Monte Carlo, the same errors for both stances).

Writes results/stance/:
  locations.csv      worker x location x stance: feasible, step_m, paper score, REBA, RULA
  headline.csv       worker x stance x start x score: optimised less shortest distance, beats
  posture_error.csv  the default worker's headline comparison under posture error, per stance
  manifest.json      with the stepping worker's optimum and how often optimised beats
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...io.atomic import atomic_write_csv
from ...landscape.stats import optimum
from ...twin.stance import STANCES
from ..choices import DEFAULT_WORKER
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import grid_of, landscape
from .comparison import headline, scored, under_posture_error

SCORE = "paper_postural"  # the stepping worker's own optimum is found on the paper's score


def default_locations(results: Path, stepping_optimum: np.ndarray) -> pd.DataFrame:
    """The default worker's headline locations: the optimised one, each start's shortest
    distance, and the stepping worker's own optimum."""
    base = pd.read_csv(results / "baselines" / "baselines.csv")
    best = base[base["method"] == "optimised"].iloc[0]
    rows = [("optimised", "", best["x"], best["y"], best["z"])]
    shortest = base[base["method"] == "shortest_distance"].reset_index(drop=True)
    rows += [("shortest distance", f"start {k + 1}", r["x"], r["y"], r["z"])
             for k, r in shortest.iterrows()]
    rows.append(("stepping optimum", "", *stepping_optimum))
    return pd.DataFrame(rows, columns=["location", "start", "x", "y", "z"]).assign(
        worker=DEFAULT_WORKER)


def participant_locations(results: Path) -> pd.DataFrame:
    """Each participant's own and default optimised locations and shortest-distance ones."""
    table = pd.read_csv(results / "participants" / "participants.csv")
    table = table[table["worker"] != DEFAULT_WORKER]  # the default worker's rows are above
    names = {"own-optimised": "own optimised", "default-optimised": "default optimised",
             "shortest-distance": "shortest distance"}
    return pd.DataFrame({"worker": table["worker"], "location": table["location"].map(names),
                         "start": table["start"].fillna(""), "x": table["x"], "y": table["y"],
                         "z": table["z"]})


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.stance

    def work(folder: Path) -> dict:
        stepping = config.evaluator(stance="step")
        print("  the stepping worker's own landscape")
        own = landscape(engine, stepping, grid_of(stepping, config.landscape.boundary,
                                                  part.step))
        own_cells, own_best = optimum(own, SCORE)
        named = pd.concat([default_locations(results, own_best), participant_locations(results)],
                          ignore_index=True)[["worker", "location", "start", "x", "y", "z"]]
        workers = list(dict.fromkeys(named["worker"]))
        evaluators = {s: {w: config.evaluator(w, stance=s) for w in workers}
                      for s in STANCES}
        print(f"  {len(named)} locations of {len(workers)} workers, planted and stepping")
        table = scored(named, evaluators)
        heads = [headline(table, "optimised").assign(optimised_location="optimised")]
        for which in ("own optimised", "default optimised"):
            heads.append(headline(table[table["worker"] != DEFAULT_WORKER], which)
                         .assign(optimised_location=which))
        head = pd.concat(heads, ignore_index=True)
        mine = named[(named["worker"] == DEFAULT_WORKER)
                     & named["location"].isin(("optimised", "shortest distance"))]
        print(f"  the default worker's comparison under posture error ({part.draws} draws)")
        errors = under_posture_error(mine.reset_index(drop=True),
                                     {s: evaluators[s][DEFAULT_WORKER] for s in STANCES},
                                     part.angle_sds, part.draws, part.seed)
        atomic_write_csv(table, folder / "locations.csv")
        atomic_write_csv(head, folder / "headline.csv")
        atomic_write_csv(errors, folder / "posture_error.csv")
        paper = head[(head["worker"] == DEFAULT_WORKER) & (head["score"] == SCORE)]
        return {"stepping_optimum": [round(float(v), 6) for v in own_best],
                "stepping_optimum_score": int(own.arrays[SCORE][own_cells[0]]),
                "optimised_beats_shortest_distance": {
                    s: f"{int(g['beats'].sum())} of {len(g)}"
                    for s, g in paper.groupby("stance", sort=False)}}

    return run_part("stance", results / "stance", config.part_inputs("stance"), work,
                    seeds={"stance": part.seed}, force=force, engine=engine)
