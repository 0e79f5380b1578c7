"""Choose the pairwise searcher's fixed length scale and preference noise.

Usage: python experiments/tools/tune_pairwise.py [--workers N] [--runs R]

Runs ``pairwise+prior`` on population workers *outside* the personalisation study's (the
population's workers 41 on: the study uses its first 30), with exact answers, posture answers
of 5° SD and a novice rater, for each pair of settings below, and prints the mean true regret
of its recommendation after 10, 25 and 50 handovers. ``search/pairwise.py`` ships the pair with
the lowest mean over the noisy answers. The landscapes are the population part's (from the
landscape cache, or swept).
"""

from __future__ import annotations

import argparse
import itertools

import pandas as pd

from ergohandover.search import pairwise
from ergohandover.study.config import StudyConfig
from ergohandover.study.personalise.measured_answers import (
    IN_MODEL,
    Answers,
    MeasuredJob,
    run_measured_job,
)
from ergohandover.study.personalise.sessions import leave_one_out_priors, run_seeds
from ergohandover.study.shared import grid_of
from ergohandover.study.workforce import bodies
from ergohandover.twin.evaluate import Evaluator

NOISES = (0.1, 0.3, 1.0)
LENGTHS_M = (0.03, 0.06)
FIRST = 40
"""Index (among the population's sampled workers) of the first worker used here."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=8, help="workers (default 8)")
    parser.add_argument("--runs", type=int, default=2, help="runs per worker (default 2)")
    args = parser.parse_args()
    config = StudyConfig()
    table = config.population.workers()
    population = pd.read_csv("results/population/workers.csv")
    evaluators = [Evaluator(b, config.task()) for b in bodies(table)]
    grid = grid_of(evaluators[-1], config.population.boundary, config.population.step)
    sampled = [i for i, r in enumerate(table["reference"]) if r == 0]
    chosen = sampled[FIRST:FIRST + args.workers]
    objective = config.personalise.objective
    priors = leave_one_out_priors(population[population["reference"] == 0], objective)
    answers = (Answers("posture", 0.0), Answers("posture", 5.0), Answers("rater", 0.51))
    for noise, length in itertools.product(NOISES, LENGTHS_M):
        pairwise.NOISE, pairwise.LENGTH_M = noise, length
        rows = []
        for model, i in itertools.product(answers, chosen):
            worker = table["worker"].iloc[i]
            rows += run_measured_job(MeasuredJob(
                worker, IN_MODEL, evaluators[i], grid, objective, "pairwise+prior", model,
                (10, 25, 50), run_seeds(1, worker, args.runs), priors[worker]))
        regret = pd.DataFrame(rows).groupby(["answers", "budget"])["regret"].mean().unstack()
        noisy = regret.drop(index="exact").to_numpy().mean()
        print(f"noise {noise:g}, length {length:g} m: mean regret over noisy answers "
              f"{noisy:.2f}\n{regret.round(2).to_string()}\n", flush=True)


if __name__ == "__main__":
    main()
