"""Why the fitted twin misses a worker's optimum: a wrong model, or a near-tie the readings
cannot split.

Usage: python experiments/tools/near_ties.py [--workers 1-30] [--runs 5] [--budget 10]
       [--answers posture:5|imu:1] [--extra-bodies N] [--offset-error SD] [--soft-optimum SD]

Runs the fitted twin as the personalisation study runs it (the study's seeds, candidates and
answers; the landscapes from the cache) and, for every run whose recommendation is not the
worker's true optimum, prints the model's probability that its recommendation is the optimum
beside the highest probability it gives any cell of the worker's true optimum, and each
worker's optimum size in cells. A miss whose true optimum the model holds nearly as probable
as its recommendation is a near-tie: at the paper score's 2-3 degree thresholds, angles read
with degrees of error cannot tell the two apart. A miss where it holds the optimum improbable
is the model's (its candidate bodies do not cover the worker).

Three questions about the model's limits:

- ``--extra-bodies N``: would more candidate bodies cover the workers better? N more bodies of
  the survey's model (the population's draw with the next seed), swept into the landscape
  cache, join every worker's candidates.
- ``--offset-error SD``: would knowing how this worker's angles differ from each candidate's
  help? After each run the recommendation is made again with every live hypothesis's angles
  moved by the worker's own offset from it (the mean difference of the worker's true angles
  and the hypothesis's at the cells handed over at), plus a Gaussian error of SD degrees on
  each angle (0: known exactly), and rescored with the paper's score; the misses of both are
  printed. Only cells within :data:`RESCORED` points of a candidate's own lowest are rescored
  (an offset of a few degrees moves a cell's score by a point or two).
- ``--soft-optimum SD``: would the middle of a plateau be safer? Each candidate's optimum is
  counted as the share of :data:`SOFT_DRAWS` offsets, drawn with SD degrees on every angle
  (the same offset at every cell), under which a cell is among the candidate's lowest,
  rescored as ``--offset-error`` rescores: a cell near a band edge counts for less. The search
  runs with it (proposals and recommendation).
"""

from __future__ import annotations

import argparse
import math
import zlib

import numpy as np
import pandas as pd

from ergohandover.ergonomics import REQUIRED_COLUMNS, Posture
from ergohandover.ergonomics.paper_score import paper_postural
from ergohandover.landscape.store import landscape_of, landscapes_of
from ergohandover.search import Budget, make
from ergohandover.search import run as run_search
from ergohandover.search.fitted_twin import FIELD_ANGLES, BodyPosterior
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
from ergohandover.study.workforce import Workforce, bodies, sample_workforce
from ergohandover.twin.evaluate import Evaluator

NEAR = 0.8
"""A miss is a near-tie when the model holds the true optimum at least this share as probable
as its recommendation."""
LIVE = 1e-3
"""Hypotheses at least this share of the heaviest are rescored with an offset."""
RESCORED = 2
"""Cells within this many points of a candidate's lowest score are rescored with an offset."""
SOFT_DRAWS = 64
"""Offsets drawn per candidate for ``--soft-optimum``."""


def paper_scores(angles: np.ndarray) -> np.ndarray:
    """The paper's score of postures given by :data:`FIELD_ANGLES` alone ((n, angles) [deg]):
    the other columns neutral, the right knee as the left."""
    columns = {c: np.zeros(len(angles)) for c in REQUIRED_COLUMNS}
    columns.update({a: angles[:, i] for i, a in enumerate(FIELD_ANGLES)})
    columns["right_knee_flexion"] = columns["left_knee_flexion"]
    return paper_postural(Posture(columns))["paper_postural"].astype(float)


def rescored(twins, candidate: int, offsets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A candidate's cells within :data:`RESCORED` points of its lowest, (cells,), and their
    paper score with each offset (offsets, :data:`FIELD_ANGLES`) [deg] added to the candidate's
    angles there, (offsets, cells)."""
    values = twins.values(candidate)
    near = np.flatnonzero(values <= values.min() + RESCORED)
    base = twins.angles(near, [candidate])[0]
    # What the field's angles do not hold (hands above the neck, say) is kept as it was.
    rest = values[near] - paper_scores(base)
    moved = (base[None] + offsets[:, None]).reshape(-1, base.shape[1])
    return near, rest + paper_scores(moved).reshape(len(offsets), -1)


def offset_recommendation(searcher, twins, true_angles: np.ndarray, error_deg: float,
                          rng: np.random.Generator) -> int:
    """The cell of highest probability of being the worker's optimum when every live
    hypothesis's angles are moved by the worker's offset from it (see the module); equal:
    nearest the prior."""
    posterior = searcher.posterior
    weights = posterior.weights
    tried = [c for c, s in searcher.told.items() if math.isfinite(s)]
    shape = tuple(int(n) for n in posterior.shape)
    sources = np.array([posterior.sources(c)[0] for c in tried])  # (tried, D)
    total = np.zeros(int(np.prod(shape)))
    live = weights >= LIVE * weights.max()
    for k in np.flatnonzero(live.any(axis=1)):
        field = twins.angles(np.arange(total.size), [int(k)])[0]
        shifts = np.flatnonzero(live[k])
        offsets = np.nan_to_num(np.nanmean(
            true_angles[tried][None] - field[sources[:, shifts].T], axis=1))  # (shifts, angles)
        offsets += rng.normal(0.0, error_deg, offsets.shape)
        near, scored = rescored(twins, int(k), offsets)
        for d, scores in zip(shifts, scored, strict=True):
            index = np.array(np.unravel_index(near[scores == scores.min()], shape)).T
            index += posterior.shifts[d]
            inside = ((index >= 0) & (index < np.array(shape))).all(axis=1)
            total[np.ravel_multi_index(tuple(index[inside].T), shape)] += weights[k, d]
    best = np.flatnonzero(total == total.max())
    return int(best[np.argmin(searcher.prior_distance[best])])


_SOFT: dict[tuple[str, float], tuple[np.ndarray, np.ndarray]] = {}
"""Each candidate's softened optimum by (name, SD), shared by every run and worker."""


class SoftOptimum(BodyPosterior):
    """The fitted twin's posterior with each candidate's optimum softened: a cell holds the
    share of offsets (SD :attr:`sd` degrees on every angle, one offset for every cell) under
    which it is among the candidate's lowest (see the module)."""

    def __init__(self, library, prior, sd: float):
        super().__init__(library, prior)
        self.sd = sd

    def optimum_of(self, candidate: int) -> tuple[np.ndarray, np.ndarray]:
        key = (self.library.names[candidate], self.sd)
        if key not in _SOFT:
            rng = np.random.default_rng(zlib.crc32(key[0].encode()))
            offsets = rng.normal(0.0, self.sd, (SOFT_DRAWS, len(FIELD_ANGLES)))
            near, scores = rescored(self.library, candidate, offsets)
            share = (scores == scores.min(axis=1, keepdims=True)).mean(axis=0)
            _SOFT[key] = near[share > 0], share[share > 0]
        return _SOFT[key]


def extra_candidates(config, grid, size: int) -> list[tuple[str, Evaluator]]:
    """``size`` more bodies of the survey's model (the population's draw with the next seed),
    their landscapes swept into the cache."""
    population = config.population
    table = sample_workforce(Workforce(size, population.seed + 1, population.female_share))
    evaluators = [Evaluator(b, config.task()) for b in bodies(table)]
    for _ in landscapes_of(evaluators, grid, workers=2):
        pass
    return [(f"survey {w}", e) for w, e in zip(table["worker"], evaluators, strict=True)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", default="1-30", help="the population's sampled workers, "
                        "first-last (default 1-30: the study's)")
    parser.add_argument("--runs", type=int, default=5, help="runs per worker (default 5)")
    parser.add_argument("--budget", type=int, default=10, help="handovers (default 10)")
    parser.add_argument("--answers", default="posture:5",
                        help="KIND:LEVEL as the study's answer models (default posture:5)")
    parser.add_argument("--extra-bodies", type=int, default=0,
                        help="more candidate bodies of the survey's model (default 0)")
    parser.add_argument("--offset-error", type=float, default=None,
                        help="recommend again with each hypothesis's angles moved by the "
                        "worker's offset from it, known to within this SD [deg]")
    parser.add_argument("--soft-optimum", type=float, default=None,
                        help="search with each candidate's optimum softened by offsets of "
                        "this SD on every angle [deg]")
    args = parser.parse_args()
    if args.extra_bodies < 0:
        parser.error(f"--extra-bodies {args.extra_bodies}: expected a whole number, at least 0")
    if args.offset_error is not None and not args.offset_error >= 0:
        parser.error(f"--offset-error {args.offset_error:g}: expected degrees, at least 0")
    if args.soft_optimum is not None and not args.soft_optimum > 0:
        parser.error(f"--soft-optimum {args.soft_optimum:g}: expected degrees, more than 0")
    first, last = map(int, args.workers.split("-"))
    kind, level = args.answers.split(":")
    answers = measured.Answers(kind, float(level))
    config = StudyConfig()
    part = config.personalise
    for flag, value in (("--offset-error", args.offset_error),
                        ("--soft-optimum", args.soft_optimum)):
        if value is not None and part.objective != "paper_postural":
            parser.error(f"{flag} rescores the paper's score; the study's objective is "
                         f"{part.objective}")
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
    if args.extra_bodies:
        candidates += extra_candidates(config, grid, args.extra_bodies)
    offset_rng = np.random.default_rng([part.seed, 1])
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
        if args.offset_error is not None:  # the worker's true angles
            truth = landscape_of(evaluator, grid, progress=False)
            true_angles = np.column_stack([truth.arrays[a] for a in FIELD_ANGLES])
        for seed in run_seeds(part.seed, worker, args.runs):
            source = answers.source(grid, evaluator, part.objective, values,
                                    measured.measurement_rng(seed, answers), {})
            searcher = make("fitted-twin", grid, seed, priors[worker], twins=twins)
            if args.soft_optimum is not None:
                searcher.posterior = SoftOptimum(twins, priors[worker], args.soft_optimum)
            run_search(searcher, source, Budget(evaluations=args.budget))
            chosen = searcher.recommend()
            p = searcher.posterior.p_optimal()
            again = chosen.cell if args.offset_error is None else offset_recommendation(
                searcher, twins, true_angles, args.offset_error, offset_rng)
            rows.append({"worker": worker, "optimum_cells": len(optimum),
                         "missed": values[chosen.cell] > values.min(),
                         "missed_with_offset": values[again] > values.min(),
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
    if args.offset_error is not None:
        print(f"with each hypothesis's offset from the worker known to within "
              f"{args.offset_error:g} deg: {int(found['missed_with_offset'].sum())} of "
              f"{len(found)} missed")


if __name__ == "__main__":
    main()
