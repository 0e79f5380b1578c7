"""Study part `personalise`: which method finds *this* worker's optimum in the fewest handovers?

A handover location is personal, and on a site or in VR each evaluation is a real handover with
a person. On the population study's first workers (each with the twin's landscape on the
population's grid standing in for the person), every searcher — the population prior alone,
Bayesian optimisation (Optuna's GP sampler, the infeasible region as a constraint), TPE,
CMA-ES, particle-swarm optimisation, Soft Actor-Critic, tabular Q-learning, a random walk and
random order; ``+prior``: warm-started by the worker's prior (a learner's episodes start at
it) — gets paired, seeded runs
until it evaluates a cell at the worker's own minimum of the objective or spends the largest
budget. Budgets are read from those runs (a run succeeds at budget B when it reached the target
within B evaluations). Then the same workers, and workers whose twin differs from the prior's,
are answered as a site would answer (:mod:`.measured_answers`: measured postures, raters, or
preferences) at equal budgets, each recommendation read against no search.

Writes results/personalise/:
  workers.csv   each worker: body, own optimum (score, cells at it, share of the grid), its
                leave-one-out prior and how far the prior lies from the nearest optimum cell
  runs.csv      one row per worker, searcher and run: evaluations to the optimum and to within
                one point of it (NaN: not within the searcher's largest budget), best found
  summary.csv   per searcher, target (optimum, within_1) and budget: workers, runs, share
                of runs that reached the target (95 % interval: bootstrap over workers, at
                least Wilson's), median evaluations to the optimum and to within one point
  curves.csv    share of runs at the target within n evaluations, per searcher
  measured_runs.csv     answers as a site gets them (measured_answers.py): per worker
                        and twin (in model, or a sensitivity variant), searcher, answer model,
                        recommendation rule, run and budget, the recommendation and its true
                        regret
  measured_summary.csv  per model (in, out), searcher, answer model, rule and budget: the
                        share of runs whose recommendation is a true optimum, the mean true
                        regret, the gain over no search and the harm (runs worse than it),
                        the handovers used and the model's stated probability, with intervals
                        over workers; "no search" rows: one handover at the prior's location
  manifest.json
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from ...io.atomic import atomic_write_csv
from ...landscape import Landscape
from ...twin.evaluate import Evaluator
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..sensitivity.variants import variants
from ..shared import grid_of, landscapes, run_jobs
from ..workforce import bodies
from .measured_answers import (
    IN_MODEL,
    MeasuredJob,
    answer_models,
    candidate_library,
    measured_summary,
    no_search,
    run_measured_job,
    truth_key,
)
from .sessions import (
    PersonaliseJob,
    leave_one_out_priors,
    prepare_values,
    run_personalise_job,
    run_seeds,
    success_curves,
    summary,
    values_for,
)
from .unknown_workers import impaired_candidates, own_candidate, unknown_twin


def worker_table(workers: pd.DataFrame, found: list[Landscape], priors: dict,
                 objective: str) -> pd.DataFrame:
    """workers.csv: each worker's body, own optimum and prior (each worker's objective computed
    here once, for this process and the workers it forks: :func:`~.sessions.prepare_values`)."""
    rows = []
    for (_, worker), landscape in zip(workers.iterrows(), found, strict=True):
        values = prepare_values(worker["worker"], objective, landscape)
        lowest = float(values.min())
        cells = np.flatnonzero(values == lowest)
        points = landscape.grid.coordinates(cells)
        prior = priors[worker["worker"]]
        miss = np.linalg.norm(points - np.asarray(prior.location), axis=1).min()
        rows.append({"worker": worker["worker"], "sex": worker["sex"],
                     "stature_m": worker["stature_m"],
                     "elbow_height_m": worker["elbow_height_m"], "optimum_score": lowest,
                     "optimum_cells": len(cells),
                     "optimum_share": len(cells) / landscape.grid.size,
                     "within_1_cells": int((values <= lowest + 1).sum()),
                     "prior_x": prior.location[0], "prior_y": prior.location[1],
                     "prior_z": prior.location[2],
                     "prior_to_optimum_m": round(float(miss), 6)})
    return pd.DataFrame(rows)


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.personalise

    def work(folder: Path) -> dict:
        table = config.population.workers()
        population = pd.read_csv(results / "population" / "workers.csv")
        task = config.task()
        evaluators = [Evaluator(body, task) for body in bodies(table)]
        grid = grid_of(evaluators[-1], config.population.boundary, config.population.step)
        chosen = table[table["reference"] == 0].head(part.workers)
        everyone = [(w, e) for w, e, r in zip(table["worker"], evaluators, table["reference"],
                                              strict=True) if r == 0]
        evaluators = evaluators[:len(chosen)]
        print(f"  {len(chosen)} workers of the population on {grid.describe()}")
        found = landscapes(engine, evaluators, grid)  # the population's: from the cache
        priors = leave_one_out_priors(population[population["reference"] == 0], part.objective)
        workers = worker_table(chosen, found, priors, part.objective)
        atomic_write_csv(workers, folder / "workers.csv")
        largest = {s: max(part.budgets_of(s)) for s in part.searchers}
        # The costliest searchers first (by the last run's own times, where there was one), so
        # that the pool's processes finish together.
        took = earlier_seconds(results / "personalise")
        searchers = sorted(part.searchers, key=lambda s: -took.get(s, 0.0))
        jobs = [PersonaliseJob(w, e, grid, part.objective, s, largest[s],
                               run_seeds(part.seed, w, part.runs), priors[w])
                for s in searchers for w, e in zip(chosen["worker"], evaluators, strict=True)]
        print(f"  {len(part.searchers)} searchers x {len(chosen)} workers x {part.runs} runs, "
              f"up to {max(largest.values()):,} evaluations each")
        started = time.perf_counter()
        rows, seconds = [], {}
        for job, (found_rows, spent) in zip(
                jobs, run_jobs(engine, timed_job, jobs, "personalise"), strict=True):
            rows += found_rows
            seconds[job.searcher] = seconds.get(job.searcher, 0.0) + spent
        order = {s: i for i, s in enumerate(part.searchers)}
        worker_order = {w: i for i, w in enumerate(chosen["worker"])}
        runs = pd.DataFrame(rows).sort_values(
            ["searcher", "worker", "run"], kind="stable", ignore_index=True,
            key=lambda c: c.map(order) if c.name == "searcher" else
            c.map(worker_order) if c.name == "worker" else c)
        budgets = {s: part.budgets_of(s) for s in part.searchers}
        atomic_write_csv(runs, folder / "runs.csv")
        atomic_write_csv(summary(runs, budgets, part.seed), folder / "summary.csv")
        atomic_write_csv(success_curves(runs, largest), folder / "curves.csv")
        measured = measured_tables(part, chosen, evaluators, grid, priors, engine, everyone)
        for name, table in measured.items():
            atomic_write_csv(table, folder / f"{name}.csv")
        return {"runs": len(runs), "searcher_seconds": {k: round(v, 1)
                                                        for k, v in seconds.items()},
                "search_wall_s": round(time.perf_counter() - started, 1),
                "measured_rows": len(measured.get("measured_runs", ()))}

    return run_part("personalise", results / "personalise", config.part_inputs("personalise"),
                    work, seeds={"runs": part.seed}, force=force, engine=engine)


def measured_tables(part, chosen: pd.DataFrame, evaluators: list[Evaluator], grid, priors: dict,
                    engine: Engine, everyone: list) -> dict[str, pd.DataFrame]:
    """The runs with answers as a site gets them, in and out of model, and their summary (none
    if the configuration asks for none). ``everyone``: (name, evaluator) of the population's
    sampled workers, the candidates of a fitted twin (each worker's are the others)."""
    models = answer_models(part.measured_sds, part.measured_iccs, part.measured_imu)
    if not (models and part.measured_searchers) or not any(part.runs_of(a) for a in models):
        return {}
    twins = [(w, IN_MODEL, e) for w, e in zip(chosen["worker"], evaluators, strict=True)]
    twins += out_of_model(part, chosen, evaluators, grid, engine)
    twins += unknown(part, chosen, evaluators, grid, engine)
    # The model of the worker (a fitted twin's, and every other searcher's recommendation):
    # the population's other workers and the other workers' impaired twins as candidates (so
    # that a restriction can be found from the angles).
    everyone = [*everyone, *impaired_candidates(twins)]
    # Bayesian optimisation's proposals cost the most: its jobs first, so the pool ends together.
    searchers = sorted(part.measured_searchers, key=lambda s: s != "bo+prior")
    # Every candidate's scores and angles, read here once for the pool's workers.
    landscapes(engine, [e for _, e in everyone], grid)  # swept if not in the cache
    candidate_library(everyone, grid, part.objective).prepare()
    jobs = [MeasuredJob(w, twin, e, grid, part.objective, s, answers,
                        tuple(part.budgets_of(s, measured=True)),
                        run_seeds(part.seed, w, part.runs_of(answers, twin)), priors[w],
                        tuple(c for c in everyone if not own_candidate(c[0], w)),
                        part.stop_level)
            for s in searchers for answers in models for w, twin, e in twins
            if part.runs_of(answers, twin)]
    baseline = pd.Series({f"{w}|{twin}": no_search(values_for(truth_key(w, twin), e, grid,
                                                              part.objective), grid, priors[w])
                          for w, twin, e in twins})
    print(f"  answers with error: {len(part.measured_searchers)} searchers x {len(models)} "
          f"answer models x {len(twins)} workers ({len(chosen)} in model); runs a worker: "
          f"{part.headline_runs} under posture SD {part.headline_sd:g} deg, "
          f"{part.measured_runs} under the others; up to {max(part.measured_budgets)} "
          "handovers each")
    rows = [row for found in run_jobs(engine, run_measured_job, jobs, "answers with error")
            for row in found]
    order = {s: i for i, s in enumerate(part.measured_searchers)}
    answer_order = {a.label: i for i, a in enumerate(models)}
    twin_order = {(w, t): i for i, (w, t, _) in enumerate(twins)}
    runs = pd.DataFrame(rows)
    runs["_twin"] = [twin_order[k] for k in zip(runs["worker"], runs["twin"], strict=True)]
    runs = runs.sort_values(
        ["searcher", "answers", "_twin", "run", "budget"], kind="stable", ignore_index=True,
        key=lambda c: c.map(order) if c.name == "searcher" else
        c.map(answer_order) if c.name == "answers" else c).drop(columns="_twin")
    seed = int(np.random.SeedSequence([part.seed, 1]).generate_state(1)[0])
    return {"measured_runs": runs, "measured_summary": measured_summary(runs, baseline, seed)}


def out_of_model(part, chosen: pd.DataFrame, evaluators: list[Evaluator], grid,
                 engine: Engine) -> list[tuple[str, str, Evaluator]]:
    """The first workers with each sensitivity variant's twin (:func:`changed_twins`)."""
    named = {v.name: v for v in variants(evaluators[0])}
    twins = [(w, name, named[name].evaluator(e)) for name in part.measured_variants
             for w, e in zip(chosen["worker"][:part.measured_variant_workers],
                             evaluators, strict=False)]
    return changed_twins(twins, part, grid, engine, "out of model", part.measured_variants)


def unknown(part, chosen: pd.DataFrame, evaluators: list[Evaluator], grid,
            engine: Engine) -> list[tuple[str, str, Evaluator]]:
    """The first workers changed into each kind the prior does not know (impaired, stepping,
    of other proportions: :func:`changed_twins`)."""
    twins = [(w, kind, unknown_twin(kind, e)) for kind in part.measured_unknown
             for w, e in zip(chosen["worker"][:part.measured_unknown_workers], evaluators,
                             strict=False)]
    return changed_twins(twins, part, grid, engine, "workers the prior does not know",
                         part.measured_unknown)


def changed_twins(twins: list[tuple[str, str, Evaluator]], part, grid, engine: Engine,
                  said: str, kinds) -> list[tuple[str, str, Evaluator]]:
    """``twins`` ((worker, kind, evaluator)), their landscapes swept (or read from the cache)
    and their scores kept for the pool's workers."""
    if twins:
        print(f"  {said}: {len(twins)} twins ({', '.join(kinds)})")
        for (w, kind, _), landscape in zip(twins, landscapes(engine, [t[2] for t in twins], grid),
                                           strict=True):
            prepare_values(truth_key(w, kind), part.objective, landscape)
    return twins


def earlier_seconds(folder: Path) -> dict[str, float]:
    """Each searcher's time in the part's last run (its manifest's), or nothing."""
    try:
        manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
        return dict(manifest["searcher_seconds"])
    except (OSError, ValueError, KeyError, TypeError):
        return {}


def timed_job(job: PersonaliseJob) -> tuple[list[dict], float]:
    """A job's rows and its own time on one core [s] (the manifest's cost per searcher)."""
    start = time.perf_counter()
    return run_personalise_job(job), time.perf_counter() - start
