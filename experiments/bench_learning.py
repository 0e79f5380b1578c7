"""Benchmark: env steps/s (landscape and online) and time to the global minimum per agent.

Usage: python experiments/bench_learning.py [--landscape FILE] [--seeds 10] [--time-cap 30]
       [--agents qlearning,randomwalk,random-draws,hillclimb,dqn] [--rate-steps 2000000]
       [--online-steps 5000]

1. Steps/s on a landscape: ``env.step()`` through the Gymnasium API, and each agent's own loop
   (the tabular learner and the search baselines call the env's transition directly).
2. Steps/s online (``evaluate()`` memoised per cell): ``env.step()`` along a random walk of
   --online-steps steps from a cold memo, then the same walk again (every cell memoised).
3. Per agent, --seeds runs (seeds 0..n-1) capped at --time-cap seconds that stop as soon as the
   landscape's global minimum is seen: the median time and steps to reach it, and how many did.

The landscape: --landscape, else the paper-code landscape of the default worker in
the landscape cache (``ergohandover sweep --boundary paper-code``), else a coarse one (12 mm
grid, ~10 s) built there. Prints figures; asserts nothing.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from ergohandover.envs import HandoverEnv, LandscapeScores, OnlineScores
from ergohandover.landscape import Landscape, cached_landscape, landscape_of
from ergohandover.landscape.grid import DEFAULT_STEP, Grid
from ergohandover.landscape.stats import exhaustive
from ergohandover.search import Budget, make, run
from ergohandover.search.qlearning import run_qlearning
from ergohandover.search.walks import run_hillclimb, run_random_draws, run_randomwalk
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary

ROOT = Path(__file__).resolve().parents[1]
TARGET_STEPS_PER_S = 50_000
COARSE_STEP = 0.012  # [m]: 34 x 61 x 26 = 54k points, a ~10 s sweep on two cores


def find_landscape(given: Path | None) -> Path:
    if given is not None:
        return given
    full = Grid(Boundary.paper_code(), DEFAULT_STEP)
    found = cached_landscape(Evaluator(), full)
    if found is not None:
        return found.path
    coarse = Grid(Boundary.paper_code(), COARSE_STEP)
    print(f"no paper-code landscape in the cache: building a coarse one ({coarse.describe()})",
          file=sys.stderr)
    return landscape_of(Evaluator(), coarse, workers=2).path


def gym_steps_per_s(env: HandoverEnv, steps: int) -> float:
    """``env.step()`` through the Gymnasium API with pre-drawn random actions."""
    actions = np.random.default_rng(0).integers(6, size=steps).tolist()
    env.reset(seed=0)
    start = time.perf_counter()
    for a in actions:
        if env.step(a)[2]:
            env.reset()
    return steps / (time.perf_counter() - start)


def agent_rate(runner, env, steps: int) -> float:
    result = runner(env, Budget(steps=steps), 0)
    return result.steps / result.elapsed_s


def online_rates(grid: Grid, steps: int) -> tuple[float, float, int]:
    """``env.step()`` steps/s online along a random walk: cold memo, then the same walk again
    (same seed and actions: every cell memoised); and how many locations were evaluated."""
    scores = OnlineScores(grid, Evaluator())
    env = HandoverEnv(scores)
    env.reset(seed=0)  # the solver's one-off setup (~1.5 s) is not part of a step
    cold = gym_steps_per_s(env, steps)
    warm = gym_steps_per_s(env, steps)
    return cold, warm, scores.evaluations


def run_one(name: str, landscape: Landscape, seed: int, budget: Budget):
    scores = LandscapeScores(landscape)
    return run(make(name, scores.grid, seed, episode_end="paper"), scores, budget)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--landscape", type=Path, help="landscape .npz (default: see above)")
    parser.add_argument("--seeds", type=int, default=10, help="runs per agent (default: 10)")
    parser.add_argument("--time-cap", type=float, default=30.0,
                        help="cap per run [s] (default: 30)")
    parser.add_argument("--agents", default="qlearning,randomwalk,random-draws,hillclimb,dqn",
                        help="comma-separated agents (default: all five)")
    parser.add_argument("--rate-steps", type=int, default=2_000_000,
                        help="steps per landscape steps/s measurement (default: 2,000,000)")
    parser.add_argument("--online-steps", type=int, default=5_000,
                        help="steps of the online walk; 0 skips it (default: 5,000)")
    args = parser.parse_args()

    path = find_landscape(args.landscape)
    start = time.perf_counter()
    landscape = Landscape.load(path)
    scores = LandscapeScores(landscape)
    print(f"landscape {path} ({landscape.grid.describe()}), loaded in "
          f"{time.perf_counter() - start:.1f} s")
    truth = exhaustive(landscape)
    print(f"global minimum paper_postural {truth.score:g} at {len(truth.cells):,} locations "
          f"({truth.fraction:.2%} of feasible); most symmetric "
          f"({truth.location[0]:.3f}, {truth.location[1]:.3f}, {truth.location[2]:.3f}) m")

    print("\nsteps/s on the landscape (one core):")
    rate = gym_steps_per_s(HandoverEnv(scores), min(args.rate_steps, 500_000))
    print(f"  env.step() via the Gymnasium API      {rate:>12,.0f} steps/s")
    for name, runner in (("qlearning", run_qlearning), ("randomwalk", run_randomwalk),
                         ("random-draws", run_random_draws), ("hillclimb", run_hillclimb)):
        rate = agent_rate(runner, HandoverEnv(scores), args.rate_steps)
        verdict = ("" if name != "qlearning" else
                   f"   (target >= {TARGET_STEPS_PER_S:,}: "
                   f"{'meets' if rate >= TARGET_STEPS_PER_S else 'MISSES'})")
        print(f"  {name:<12} agent loop                {rate:>12,.0f} steps/s{verdict}")
    if args.online_steps > 0:
        cold, warm, evaluated = online_rates(landscape.grid, args.online_steps)
        print(f"online (evaluate() memoised, 4x4x4 blocks), env.step() along a random walk "
              f"of {args.online_steps:,} steps:")
        print(f"  cold memo {cold:,.0f} steps/s ({evaluated:,} locations evaluated); "
              f"memoised {warm:,.0f} steps/s")

    agents = [a.strip() for a in args.agents.split(",") if a.strip()]
    print(f"\ntime to the global minimum ({truth.score:g}), {args.seeds} seeds per agent, cap "
          f"{args.time_cap:g} s per run, stopping when reached:")
    print(f"  {'agent':<10} {'reached':>8} {'median s':>10} {'median steps':>13} "
          f"{'max s':>8} {'steps/s':>10}")
    for name in agents:
        times, steps, rates, reached = [], [], [], 0
        for seed in range(args.seeds):
            budget = Budget(seconds=args.time_cap, stop_score=truth.score)
            result = run_one(name, landscape, seed, budget)
            hit = result.best_score <= truth.score
            reached += hit
            t, s = result.first_reached
            times.append(t if hit else float("inf"))
            steps.append(s if hit else float("inf"))
            rates.append(result.steps / max(result.elapsed_s, 1e-9))
        print(f"  {name:<10} {f'{reached}/{args.seeds}':>8} {statistics.median(times):>10.3f} "
              f"{statistics.median(steps):>13,.0f} {max(times):>8.3f} "
              f"{statistics.median(rates):>10,.0f}")
    print(f"\nbenchmark wall time {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
