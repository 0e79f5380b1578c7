"""Why the fitted twin misses a worker's optimum: a wrong model, or a near-tie the readings
cannot split.

Usage: python experiments/tools/near_ties.py [--workers 1-30] [--runs 5] [--budget 10]
       [--answers posture:5|imu:1]

Runs the fitted twin as the personalisation study runs it (the study's seeds, candidates and
answers; the landscapes from the cache) and, for every run whose recommendation is not the
worker's true optimum, prints the model's probability that its recommendation is the optimum
beside the highest probability it gives any cell of the worker's true optimum, and each
worker's optimum size in cells. A miss whose true optimum the model holds nearly as probable
as its recommendation is a near-tie: at the paper score's 2-3 degree thresholds, angles read
with degrees of error cannot tell the two apart. A miss where it holds the optimum improbable
is the model's (its candidate bodies do not cover the worker).
"""

from __future__ import annotations

import argparse

import numpy as np
import pandas as pd

from ergohandover.search import Budget, make
from ergohandover.search import run as run_search
from ergohandover.study.config import StudyConfig
from ergohandover.study.personalise import measured_answers as measured
from ergohandover.study.personalise.sessions import (
    leave_one_out_priors,
    run_seeds,
)
from ergohandover.study.personalise.unknown_workers import (
    IMPAIRED,
    group_of,
    impaired_candidates,
    own_candidate,
    unknown_twin,
)
from ergohandover.study.shared import grid_of
from ergohandover.study.workforce import bodies
from ergohandover.twin.evaluate import Evaluator

NEAR = 0.8
"""A miss is a near-tie when the model holds the true optimum at least this share as probable
as its recommendation."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", default="1-30", help="the population's sampled workers, "
                        "first-last (default 1-30: the study's)")
    parser.add_argument("--runs", type=int, default=5, help="runs per worker (default 5)")
    parser.add_argument("--budget", type=int, default=10, help="handovers (default 10)")
    parser.add_argument("--answers", default="posture:5",
                        help="KIND:LEVEL as the study's answer models (default posture:5)")
    args = parser.parse_args()
    first, last = map(int, args.workers.split("-"))
    kind, level = args.answers.split(":")
    answers = measured.Answers(kind, float(level))
    config = StudyConfig()
    part = config.personalise
    table = config.population.workers()
    population = pd.read_csv("results/population/workers.csv")
    evaluators = [Evaluator(b, config.task()) for b in bodies(table)]
    grid = grid_of(evaluators[-1], config.population.boundary, config.population.step)
    everyone = [(w, e) for w, e, r in zip(table["worker"], evaluators, table["reference"],
                                          strict=True) if r == 0]
    priors = leave_one_out_priors(population[population["reference"] == 0], part.objective)
    changed = [(w, k, unknown_twin(k, e)) for k in part.measured_unknown
               if group_of(k) == IMPAIRED for w, e in everyone[:part.measured_unknown_workers]]
    candidates = [*everyone, *impaired_candidates(changed)]
    rows = []
    for worker, evaluator in everyone[first - 1:last]:
        job = measured.MeasuredJob(worker, measured.IN_MODEL, evaluator, grid, part.objective,
                                   "fitted-twin", answers, (args.budget,), (), priors[worker])
        values = measured.truth_of(job)
        optimum = np.flatnonzero(values == values.min())
        body = evaluator.body
        twins = measured.candidate_library(
            [c for c in candidates if not own_candidate(c[0], worker)], grid, part.objective,
            worker=(body.stature_m, body.sex), angle_sd_deg=measured.angle_sds(answers),
            error=answers.error)
        for seed in run_seeds(part.seed, worker, args.runs):
            source = answers.source(grid, evaluator, part.objective, values,
                                    measured.measurement_rng(seed, answers), {})
            searcher = make("fitted-twin", grid, seed, priors[worker], twins=twins)
            run_search(searcher, source, Budget(evaluations=args.budget))
            chosen = searcher.recommend()
            p = searcher.posterior.p_optimal()
            rows.append({"worker": worker, "optimum_cells": len(optimum),
                         "missed": values[chosen.cell] > values.min(),
                         "p_recommended": chosen.p_optimal, "p_true": float(p[optimum].max())})
        print(f"{worker}: {sum(r['missed'] for r in rows if r['worker'] == worker)} of "
              f"{args.runs} missed", flush=True)
    found = pd.DataFrame(rows)
    missed = found[found["missed"]]
    near = missed["p_true"] >= NEAR * missed["p_recommended"]
    print(missed.round(3).to_string(index=False))
    print(f"{len(missed)} of {len(found)} runs missed the optimum after {args.budget} handovers "
          f"({answers.label}); {int(near.sum())} were near-ties (the true optimum at least "
          f"{NEAR:.0%} as probable as the recommendation)")


if __name__ == "__main__":
    main()
