"""Benchmark: the cost of each ask/tell searcher per evaluation as its history grows, and SAC's
steps per second.

Usage: python experiments/bench_searchers.py
       [--searchers random-order,prior,bo,tpe,cmaes,pso,pairwise] [--sizes 10,100,250,1000]
       [--cap 120] [--seed 0] [--sac-steps 1000]

The grid is the population study's: the paper-code boundary every 1 cm (41 x 73 x 31 = 92,783
cells), scored for the default worker (its landscape from the cache, else swept there, ~1 min
on two cores). The scores are read from the landscape, so what is timed is the searcher: one
``ask`` and one ``tell`` per evaluation.

1. Each searcher runs once (``--seed``, no stop at the optimum) for the largest size or until
   ``--cap`` seconds; the cost at n evaluations is the mean wall time of evaluations
   n − 9 ... n (1 ... 10 at n = 10). A throwaway run first loads each searcher's libraries.
2. A size the run did not reach within the cap (the GP sampler's larger ones) is measured on
   an Optuna study preloaded with n − 1 trials at random cells (their true scores and
   feasibility): the median of 3 asks and tells, marked ``*``. That is the sampler's cost at
   that history length, whatever the cells.
3. The ratio to random order (``random-order``) at the same size, from the same process.
4. SAC (``run_sac`` on the continuous env over the same landscape): steps per second between
   a run of ``--sac-steps`` / 5 and one of ``--sac-steps`` steps (SB3's setup cancels out).

Prints figures; asserts nothing. Runs on one core (BLAS and torch limited to one thread).
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time

import numpy as np
from threadpoolctl import threadpool_limits

from ergohandover.envs import ArrayScores, ContinuousHandoverEnv, LandscapeScores
from ergohandover.envs.scores import objective_values
from ergohandover.landscape import cached_landscape, landscape_of
from ergohandover.landscape.grid import Grid
from ergohandover.search import Budget, make, run
from ergohandover.search.optuna_searchers import OptunaSearcher
from ergohandover.search.prior import shipped_prior
from ergohandover.search.sac import run_sac
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary

STEP = 0.01  # [m]: the population study's grid
REFERENCE = "random-order"
WINDOW = 10  # evaluations averaged for the cost at a size
PRELOADED_ASKS = 3


def landscape_values(grid: Grid) -> tuple[object, np.ndarray]:
    evaluator = Evaluator()
    landscape = cached_landscape(evaluator, grid)
    if landscape is None:
        print(f"sweeping the default worker's landscape ({grid.describe()})", file=sys.stderr)
        landscape = landscape_of(evaluator, grid, workers=2)
    return landscape, objective_values(landscape, "paper_postural")


def timed_run(name: str, grid: Grid, values: np.ndarray, size: int, cap_s: float, seed: int,
              prior) -> list[float]:
    """Wall time [s] of each evaluation (ask + tell) of one run, until ``size`` or the cap."""
    stamps = [time.perf_counter()]

    class Stamped(ArrayScores):
        def score(self, flat: int) -> float:
            stamps.append(time.perf_counter())
            return super().score(flat)

    budget = Budget(evaluations=size, seconds=cap_s if math.isfinite(cap_s) else None)
    run(make(name, grid, seed, prior), Stamped(grid, values), budget)
    return np.diff(stamps).tolist()


def preloaded_cost(name: str, grid: Grid, values: np.ndarray, n: int, seed: int) -> float:
    """Median wall time [s] of an ask and tell after n − 1 trials at random cells."""
    searcher = make(name, grid, seed)
    assert isinstance(searcher, OptunaSearcher)
    cells = np.random.default_rng(seed).choice(grid.size, size=n - 1, replace=False)
    searcher.add_known([(c, values[c]) for c in cells.tolist()])
    times = []
    for _ in range(PRELOADED_ASKS):
        start = time.perf_counter()
        cell = searcher.ask()
        searcher.tell(cell, values[cell])
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def sac_steps_per_s(landscape, steps: int, seed: int) -> float:
    times = []
    for n in (steps // 5, steps):
        env = ContinuousHandoverEnv(LandscapeScores(landscape), episode_end="none")
        start = time.perf_counter()
        run_sac(env, Budget(steps=n), seed)
        times.append(time.perf_counter() - start)
    return (steps - steps // 5) / (times[1] - times[0])


def main() -> int:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--searchers", default=f"{REFERENCE},prior,bo,tpe,cmaes,pso,pairwise")
    parser.add_argument("--sizes", default="10,100,250,1000")
    parser.add_argument("--cap", type=float, default=120.0, help="seconds per run")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--sac-steps", type=int, default=1000)
    args = parser.parse_args()
    names = args.searchers.split(",")
    sizes = [int(s) for s in args.sizes.split(",")]
    threadpool_limits(limits=1)

    grid = Grid(Boundary.paper_code(), STEP)
    landscape, values = landscape_values(grid)
    print(f"{grid.describe()}; minimum {values.min():g}; {np.isinf(values).mean():.1%} "
          f"infeasible; seed {args.seed}; cap {args.cap:g} s per run")
    prior = shipped_prior().predict(1.756, "male")  # the default worker (p50 man)

    costs: dict[str, dict[int, str]] = {}
    seconds: dict[str, dict[int, float]] = {}
    for name in names:
        run_prior = prior if name == "prior" else None
        timed_run(name, grid, values, 12, math.inf, args.seed + 1, run_prior)  # imports
        started = time.perf_counter()
        times = timed_run(name, grid, values, max(sizes), args.cap, args.seed, run_prior)
        wall = time.perf_counter() - started
        costs[name], seconds[name] = {}, {}
        for n in sizes:
            if len(times) >= n:
                value, mark = float(np.mean(times[max(0, n - WINDOW):n])), ""
            elif name in ("bo", "tpe"):
                value, mark = preloaded_cost(name, grid, values, n, args.seed), "*"
            else:
                value, mark = math.nan, "-"
            seconds[name][n] = value
            costs[name][n] = f"{value:.2g}{mark}" if math.isfinite(value) else mark
        print(f"{name}: {len(times)} evaluations in {wall:.1f} s", file=sys.stderr, flush=True)

    header = "| searcher | " + " | ".join(f"s/eval at {n}" for n in sizes) + " | " + \
        " | ".join(f"x {REFERENCE} at {n}" for n in sizes) + " |"
    print(header)
    print("|" + "---|" * (1 + 2 * len(sizes)))
    for name in names:
        ratios = [seconds[name][n] / seconds[REFERENCE][n] if REFERENCE in seconds
                  else math.nan for n in sizes]
        print(f"| {name} | " + " | ".join(costs[name][n] for n in sizes) + " | " +
              " | ".join(f"{r:,.0f}" if math.isfinite(r) else "-" for r in ratios) + " |")
    print("(* measured after preloading n - 1 random trials; - not reached within the cap)")
    if args.sac_steps > 0:
        rate = sac_steps_per_s(landscape, args.sac_steps, args.seed)
        print(f"SAC: {rate:,.0f} steps/s (one thread; {args.sac_steps // 5:,} and "
              f"{args.sac_steps:,}-step runs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
