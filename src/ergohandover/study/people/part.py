"""Study part `people`: the twin beside Kim et al.'s 1,000 measured human-human handovers (ICRA
2025; derived figures in src/ergohandover/study/people/measured_handovers.csv, the data outside the
project): where people received, how far the twin sized to each receiver predicts their
posture, how far they received from the twin's recommendation, and a fit of the twin's weights
held out (src/ergohandover/study/people/beside_people.py).

Writes results/people/handovers.csv (per handover: split, the receiving location, the twin's
size, the measured and predicted angles of the default and the fitted twin, the twin's scores
where people received and people's measured score intervals), locations.csv (the receiving
location's statistics), errors.csv (per twin, split and angle: N, median |error| with its 95 %
bootstrap interval, RMSE, bias), recommendation.csv (per score: the one-handed optimum of the
median receiver's twin and people's distances from it), fit.csv (every evaluation of the fit),
study_task.csv (the default and the fitted twin on the study's 14 published conditions) and
manifest.json.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...io.atomic import atomic_write_csv
from ...landscape.stats import optimum
from ...twin.evaluate import Evaluator
from ...twin.solver import SolverSettings
from ...twin.task import TaskSpec
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import default_landscape, grid_of, landscape
from ..validation.published import validation_table
from .beside_people import (
    ANGLES,
    SCORES,
    errors,
    fit,
    fit_loss,
    fitted_settings,
    location_columns,
    location_table,
    measured_angles,
    measured_handovers,
    predict,
    receiver_body,
    receiving_points,
    recommendation,
    source,
    split,
)

BOOTSTRAP = 2000
"""Resamples of each median's 95 % interval."""


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.people

    def work(folder: Path) -> dict:
        used, dropped = measured_handovers()
        print(f"  {len(used)} handovers used, {int(dropped.sum())} dropped")
        task = TaskSpec.holding(part.object)
        bodies = [receiver_body(row) for row in used.itertuples()]
        groups = split(used, part.train_share, part.seed)
        measured = measured_angles(used)
        default = predict(used, bodies, task)
        train = np.flatnonzero(groups == "train")
        factors, history = fit(used.iloc[train].reset_index(drop=True),
                               [bodies[i] for i in train], task, part.fit_weights,
                               part.fit_evaluations)
        fitted_weights = fitted_settings(factors, SolverSettings())
        fitted = predict(used, bodies, task, fitted_weights)
        rng = np.random.default_rng([part.seed, 1])  # the bootstrap's own (the split's: seed)
        table = pd.concat([errors(measured, twin, groups, rng, BOOTSTRAP).assign(twin=name)
                           for name, twin in (("default", default), ("fitted", fitted))],
                          ignore_index=True)
        atomic_write_csv(table, folder / "errors.csv")
        losses = {name: {group: round(fit_loss(measured[groups == group],
                                               twin[groups == group]), 3)
                         for group in ("train", "held-out", "out-of-distribution")}
                  for name, twin in (("default", default), ("fitted", fitted))}
        print(f"  angle RMSE held out: default twin {losses['default']['held-out']:.1f} deg, "
              f"fitted {losses['fitted']['held-out']:.1f} deg")
        atomic_write_csv(pd.DataFrame(history), folder / "fit.csv")
        statures = np.array([body.stature_m for body in bodies])
        places = location_columns(used, statures)
        atomic_write_csv(location_table(places), folder / "locations.csv")
        # The recommendation: the one-handed optimum of the median receiver's twin.
        median = used[["thigh_m", "shank_m", "upper_arm_m", "forearm_m",
                       "shoulder_height_m"]].median()
        twin = Evaluator(receiver_body(median), TaskSpec.holding(part.object, hands="right"))
        found = landscape(engine, twin, grid_of(twin, part.boundary, part.step))
        advice = recommendation(found, receiving_points(used), default, used)
        atomic_write_csv(advice, folder / "recommendation.csv")
        # The fitted twin on the study's own task, beside the default twin.
        best = optimum(default_landscape(config, engine), config.validation.optimum_of)[1]
        study_task = pd.concat([validation_table(best, Evaluator(task=config.task(),
                                                                 settings=weights))
                                .assign(weights=name)
                                for name, weights in (("default", SolverSettings()),
                                                      ("fitted", fitted_weights))],
                               ignore_index=True)
        atomic_write_csv(study_task, folder / "study_task.csv")
        rows = pd.concat([used[["handover", "kind", "receiving_hand"]].assign(split=groups),
                          places, pd.DataFrame({"stature_m": statures}),
                          measured.add_prefix("measured_"), default.add_prefix("twin_"),
                          fitted[list(ANGLES)].add_prefix("fitted_"),
                          used[[f"{s}_{e}" for s in SCORES for e in ("lo", "hi")]]
                          .add_prefix("people_")], axis=1)
        atomic_write_csv(rows.round(4), folder / "handovers.csv")
        within = study_task.groupby("weights")["within"].sum().astype(int).to_dict()
        print(f"  the study's published conditions met: default twin {within['default']}, "
              f"fitted {within['fitted']} of {len(study_task) // 2}")
        return {"source": source(), "handovers": len(used), "dropped": {
            str(reason): int(n) for reason, n in dropped.items()},
            "splits": {str(k): int(v) for k, v in zip(*np.unique(groups, return_counts=True),
                                                       strict=True)},
            "object": part.object, "fit_factors": factors, "fit_evaluations": len(history),
            "angle_rmse_deg": losses, "published_conditions_within": within,
            "median_receiver_twin": {"stature_m": twin.body.stature_m,
                                     "mass_kg": twin.body.mass_kg}}

    return run_part("people", results / "people", config.part_inputs("people"), work,
                    seeds={"people": part.seed}, force=force, engine=engine)
