"""Study part `people`: the twin beside Kim et al.'s 1,000 measured human-human handovers (ICRA
2025; derived figures in src/ergohandover/study/people/measured_handovers.csv, the data outside the
project): where people received, how far the twin sized to each receiver predicts their
posture against predictors that need no twin, where they received against the twin's
recommendation, whether the twin's scores rank people's, and a fit of the twin's weights held
out (src/ergohandover/study/people/: beside_people.py, skill.py, receiving.py).

Writes results/people/handovers.csv (per handover: split, the receiving location, the twin's
size, the measured angles and those of every predictor, the twin's scores where people received,
people's measured score intervals, their standing neutrals and each angle's spread around the
transfer), skill.csv (per group, predictor and angle: RMSE, skill
against the constant with its 95 % bootstrap interval, bias, the noise ceiling), locations.csv
(the receiving location's statistics), receiving.csv (per score and group: the twin's
one-handed optimum as the predicted receiving point against the training split's mean point),
ranking.csv (per score and group: the rank correlation of the twin's and people's scores),
recommendation.csv (per score: the one-handed optimum of the median receiver's twin and
people's distances from it, with the null of hands moved at random), fit.csv (every evaluation
of the fit), study_task.csv (the default and the fitted twin on the study's 14 published
conditions) and manifest.json.
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
    CALIBRATED,
    SCORES,
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
    receiving_side,
    recommendation,
    source,
    split,
)
from .receiving import ranking_table, where_table
from .skill import ceiling, inputs, predictions, skill_table

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
        statures = np.array([body.stature_m for body in bodies])
        places = location_columns(used, statures)
        predicted = predictions(measured, inputs(places, statures),
                                {"twin": default, "fitted twin": fitted}, groups == "train")
        skill = skill_table(measured, predicted, groups, ceiling(used), rng, BOOTSTRAP)
        atomic_write_csv(skill, folder / "skill.csv")
        losses = {name: {group: round(fit_loss(measured[groups == group],
                                               twin[groups == group]), 3)
                         for group in ("train", "held-out", "out-of-distribution")}
                  for name, twin in (("default", default), ("fitted", fitted))}
        held = skill[(skill["group"] == "held-out") & (skill["angle"] == "all six")].set_index(
            "predictor")
        print("  angle RMSE held out [deg]: " + ", ".join(
            f"{name} {held.loc[name, 'rmse_deg']:.1f}" for name in held.index))
        atomic_write_csv(pd.DataFrame(history), folder / "fit.csv")
        atomic_write_csv(location_table(places), folder / "locations.csv")
        # The recommendation: the one-handed optimum of the median receiver's twin.
        median = used[["thigh_m", "shank_m", "upper_arm_m", "forearm_m",
                       "shoulder_height_m"]].median()
        twin = Evaluator(receiver_body(median), TaskSpec.holding(part.object, hands="right"))
        found = landscape(engine, twin, grid_of(twin, part.boundary, part.step))
        advice = recommendation(found, receiving_points(used), default, used,
                                np.random.default_rng([part.seed, 2]))
        atomic_write_csv(advice, folder / "recommendation.csv")
        atomic_write_csv(where_table(found, receiving_points(used), groups,
                                     np.random.default_rng([part.seed, 3]), BOOTSTRAP),
                         folder / "receiving.csv")
        atomic_write_csv(ranking_table(default, used, groups,
                                       np.random.default_rng([part.seed, 4]), BOOTSTRAP),
                         folder / "ranking.csv")
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
                          *[pd.DataFrame(predicted[name], columns=list(ANGLES)).add_prefix(
                              f"{name.replace(' + ', '_').replace(' ', '_')}_")
                            for name in ("constant", "line", "neighbours", "line + twin")],
                          used[[f"{s}_{e}" for s in SCORES for e in ("lo", "hi")]]
                          .add_prefix("people_"),
                          pd.DataFrame({f"neutral_{a}": receiving_side(used, a, "neutral_")
                                        for a in CALIBRATED}),
                          ceiling(used).add_prefix("spread_")], axis=1)
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
