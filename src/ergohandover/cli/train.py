"""``ergohandover train``: search the handover grid with a learner or a baseline, under a cap."""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time
from pathlib import Path

from tqdm import tqdm

from ..envs.handover_env import EPISODE_ENDS, EPISODE_STEPS
from ..envs.scores import OBJECTIVES
from ..io.csv_input import InputError
from ..landscape.store import cached_landscape
from ..search.prior import Prior, shipped_prior
from ..search.qlearning import TEMPERATURES, QLearningConfig
from ..search.registry import SEARCHERS, entry
from . import defaults
from .options import (
    add_evaluator_arguments,
    add_grid_arguments,
    add_output_folder_argument,
    evaluator_from_args,
    grid_from_args,
    model_flags_given,
    run_folder,
)
from .parser import given
from .refusals import read_landscape
from .values import choice, existing_file, number, whole

Q = QLearningConfig()
DESCRIPTION = f"""\
Search the grid of box locations for the lowest ergonomic score with tabular Q-learning (the
paper's: alpha {Q.alpha:g}, gamma {Q.gamma:g}, Q = 0, softmax with temperature {Q.tau:g};
qlearning-adaptive: the paper's text's adaptive temperature), DQN (stable-baselines3), a random
walk (the learner's moves and restarts, no learning), random draws (uniform, with replacement),
hill-climbing with random restarts, SAC (stable-baselines3, moves of up to 5 cells per axis),
or an ask/tell searcher: random-order (uniform, without replacement), bo (Bayesian
optimisation, Optuna's GP sampler), tpe, cmaes, pso, their +prior variants, or prior (the
population prior for the worker of --stature/--sex or --percentile; not with --landscape), whose
steps are distinct evaluations, until a wall-clock or step cap.
Scores come from --landscape (a landscape file), else from the landscape cache when the grid of
--boundary/--step for this worker was swept before (`ergohandover sweep` or the study), else
they are computed online (memoised). Writes trace.csv (time_s, step, best score and its x, y, z
after every improvement), best_locations.csv (every location found at the best score, the most
symmetric first), q_table.npz (Q-learning: visited states only) or dqn_model.zip (sac_model.zip
for SAC), and manifest.json into --output (default: a new runs/train/<timestamp>/)."""


def time_cap_help() -> str:
    caps = defaults.paper_wall_caps()
    paper = "" if caps is None else (f" (the paper's: {' and '.join(f'{c:g}' for c in caps)}; "
                                     f"{defaults.PAPER_CONFIG})")
    return f"wall-clock cap [s]{paper}"


def target_help() -> str:
    """The paper's target and, where the study recorded it, the twin's own minimum."""
    minimum = defaults.recorded_minimum(defaults.OBJECTIVE)
    twin = ("" if minimum is None else
            f"; the twin's own minimum of {defaults.OBJECTIVE} on the default grid is "
            f"{minimum:g}, as the study computed it ({defaults.LANDSCAPE_STATS})")
    return (f"with --episode-end paper: the episode ends when the score is at most E (default: "
            f"{defaults.PAPER_TARGET:g}, the paper's target{twin})")


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "train", help="learn or search the best handover location under a time or step cap",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--agent", required=True, type=choice(tuple(SEARCHERS)),
                        metavar="|".join(SEARCHERS), help="the learner, walk or searcher")
    caps = parser.add_argument_group("budget (give exactly one)")
    caps.add_argument("--time-cap", type=number(0, None, "s", above=True), metavar="S",
                      help=time_cap_help())
    caps.add_argument("--steps", type=whole(1), metavar="N",
                      help="step cap [env steps; distinct evaluations for the ask/tell "
                      "searchers]; deterministic")
    parser.add_argument("--seed", type=whole(0), default=defaults.SEED, metavar="K",
                        help=f"seed, an integer >= 0 (default: {defaults.SEED})")
    parser.add_argument("--objective", type=choice(OBJECTIVES), default=defaults.OBJECTIVE,
                        metavar="|".join(OBJECTIVES),
                        help=f"score to minimise (default: {defaults.OBJECTIVE}, the paper's)")
    parser.add_argument("--temperature", type=choice(TEMPERATURES),
                        default=defaults.TEMPERATURE, metavar="|".join(TEMPERATURES),
                        help=f"with --agent qlearning: fixed {Q.tau:g} (the published code) or "
                        f"adaptive (the paper's text; bounded {Q.tau_bounds[0]:g}-"
                        f"{Q.tau_bounds[1]:g}), the same as --agent qlearning-adaptive "
                        f"(default: {defaults.TEMPERATURE})")
    parser.add_argument("--target", type=number(0, None), default=defaults.PAPER_TARGET,
                        metavar="E", help=target_help())
    parser.add_argument("--episode-end", type=choice(EPISODE_ENDS),
                        default=defaults.EPISODE_END, metavar="|".join(EPISODE_ENDS),
                        help="paper: at the target; none: only by truncation, the study's "
                        "(the paper's end tells the learner where the optimum is and teaches it "
                        f"to avoid it: docs/learning.md) (default: {defaults.EPISODE_END})")
    parser.add_argument("--episode-steps", type=whole(1), default=EPISODE_STEPS,
                        metavar="N", help="truncate episodes after N steps, then restart at a "
                        f"random cell (default: {EPISODE_STEPS})")
    parser.add_argument("--landscape", type=existing_file, metavar="FILE",
                        help="read scores from this landscape file; its grid is used. Without "
                        "it: the landscape cache's for --boundary/--step if swept before, else "
                        "online")
    add_grid_arguments(parser, "grid boundary: the published learner's, the paper's "
                       "body-derived one or explicit ranges in metres", "online grid step [m]")
    add_evaluator_arguments(parser, solver=False)
    add_output_folder_argument(parser, "result directory (created if needed; default: a new "
                               "runs/train/<timestamp>/)")
    parser.set_defaults(run=run)


def parse(args: argparse.Namespace) -> dict:
    """The run's resolved config: every flag was checked while parsing; here only what takes
    two flags (a one-line InputError naming them)."""
    if (args.time_cap is None) == (args.steps is None):
        raise InputError("give exactly one of --time-cap S or --steps N (got "
                         f"{'neither' if args.time_cap is None else 'both'})")
    name = args.agent
    if entry(name).twins:
        raise InputError(f"--agent {name} needs candidate twins of the worker (the "
                         "personalisation study's measured comparison runs it)")
    if entry(name).answers != "scores":
        raise InputError(f"--agent {name}: it is told which of two handovers was better, not "
                         "scores, and train reports the lowest score a run evaluated (use "
                         "ergohandover personalise --answers pairwise)")
    if args.temperature == "adaptive":
        if "temperature" not in entry(name).options:
            raise InputError(f"--temperature adaptive cannot be used with --agent {name} "
                             "(Q-learning's only: use --agent qlearning)")
        name = "qlearning-adaptive"
    if entry(name).prior == "needs" and args.landscape is not None:
        raise InputError(f"--agent {name} cannot be used with --landscape (its prior is the "
                         "population prior for the worker, which a landscape file does not "
                         "record)")
    config = {"agent": name, "time_cap_s": args.time_cap, "steps": args.steps,
              "seed": args.seed, "objective": args.objective, "target": args.target,
              "episode_end": args.episode_end, "episode_steps": args.episode_steps,
              "landscape": args.landscape}
    if args.landscape is not None:
        grid_flags = [f"--{dest}" for dest in ("boundary", "step") if dest in given(args)]
        fixed = grid_flags + model_flags_given(args)
        if fixed:
            raise InputError(f"{fixed[0]} cannot be used with --landscape (the landscape fixes "
                             "the grid, worker and task)")
    else:
        config["boundary"], config["step"] = args.boundary, args.step
    return config


def build_scores(config: dict, args: argparse.Namespace):
    """The score source and what it was built from (landscape or online evaluator and grid)."""
    from ..envs import LandscapeScores, OnlineScores

    if config["landscape"] is not None:
        landscape = read_landscape(config["landscape"], "--landscape")
    else:  # the landscape cache holds this grid's landscape if it was swept before
        evaluator = evaluator_from_args(args)
        grid = grid_from_args(evaluator, config["boundary"], config["step"])
        landscape = cached_landscape(evaluator, grid)
    if landscape is not None:
        scores = LandscapeScores(landscape, config["objective"])
        source = {"landscape": str(landscape.path), "landscape_key": landscape.key}
    else:
        # Only an agent that walks uses a cell's neighbours next: for one that jumps, prefetching
        # a cube of them would be waste.
        spec = entry(config["agent"])
        jumps = spec.kind == "searcher" or spec.name == "random-draws"
        scores = OnlineScores(grid, evaluator, config["objective"], block=1 if jumps else 4)
        source = {"evaluator": dataclasses.asdict(evaluator)}
    source["grid"] = dataclasses.asdict(scores.grid)
    if entry(config["agent"]).prior == "needs":
        source["prior"] = dataclasses.asdict(worker_prior(evaluator))
    return scores, landscape, source


def worker_prior(evaluator) -> Prior:
    """The shipped population prior's expected optimum for the run's worker."""
    body = evaluator.body
    return shipped_prior().predict(body.stature_m, body.sex)


def _bar(config: dict) -> tqdm:
    if config["time_cap_s"] is not None:
        return tqdm(total=round(config["time_cap_s"], 1), unit="s", desc=config["agent"],
                    file=sys.stderr, disable=config["time_cap_s"] < 5,
                    bar_format="{l_bar}{bar}| {n:.0f}/{total:.0f} s {postfix}")
    spec = entry(config["agent"])
    slow = (100 if spec.kind == "searcher" else 1_000 if spec.name == "sac"
            else 10_000 if spec.name == "dqn" else 2_000_000)
    return tqdm(total=config["steps"], unit="step", unit_scale=True, desc=config["agent"],
                file=sys.stderr, disable=config["steps"] < slow)


def run(args: argparse.Namespace) -> int:
    config = parse(args)
    started = time.perf_counter()
    scores, landscape, source = build_scores(config, args)
    with _bar(config) as bar:
        def progress(steps: int, elapsed: float) -> None:
            done = min(elapsed, bar.total) if config["time_cap_s"] else steps
            bar.set_postfix_str(f"{steps:,} steps", refresh=False)
            bar.update(done - bar.n)  # redraws at most every 0.1 s

        from ..search import Budget, make
        from ..search import run as run_search

        prior = Prior(**source["prior"]) if "prior" in source else None
        searcher = make(config["agent"], scores.grid, config["seed"], prior,
                        episode_end=config["episode_end"], target=config["target"],
                        episode_steps=config["episode_steps"])
        budget = Budget.of(entry(config["agent"]).unit, config["steps"], config["time_cap_s"])
        result = run_search(searcher, scores, budget, progress)
    output = args.output or run_folder("train")
    from ..landscape.stats import exhaustive
    from ..search.record import write_record

    truth = exhaustive(landscape, config["objective"]) if landscape is not None else None
    extra = {"steps_per_s": round(result.steps / max(result.elapsed_s, 1e-9), 1)}
    if truth is not None:
        extra.update(global_minimum=truth.score, reached_global_minimum=bool(
            result.best_score <= truth.score))
    resolved = {**{k: (str(v) if isinstance(v, Path) else v) for k, v in config.items()},
                **source, "agent_config": result.settings, "output": str(output)}
    paths = write_record(result, scores.grid.point, output, resolved,
                         seeds={"run": config["seed"]}, extra=extra)
    report(result, scores.grid, config, truth, time.perf_counter() - started)
    for path in paths:
        print(f"wrote {path}", file=sys.stderr)
    return 0


def report(result, grid, config: dict, truth, wall_s: float) -> None:
    """The run's summary on standard output."""
    objective = config["objective"]
    if math.isinf(result.best_score):
        print(f"{result.searcher} seed {config['seed']}: no feasible location seen in "
              f"{result.steps:,} steps")
        return
    cells = list(result.best_cells)
    from ..search.record import best_locations

    top = best_locations(result, grid.point).iloc[0]
    time_s, step = result.first_reached
    print(f"{result.searcher} seed {config['seed']}: best {objective} {result.best_score:g} at "
          f"(x, y, z) = ({top.x:.3f}, {top.y:.3f}, {top.z:.3f}) m (most symmetric of "
          f"{len(cells):,} locations found at it)")
    print(f"first reached after {time_s:.2f} s, step {step:,}; ran {result.steps:,} steps in "
          f"{result.elapsed_s:.1f} s ({result.steps / max(result.elapsed_s, 1e-9):,.0f} "
          f"steps/s; stopped by {result.stopped_by}; {wall_s:.1f} s with setup)")
    if truth is not None:
        x, y, z = truth.location
        reached = "reached" if result.best_score <= truth.score else "NOT reached"
        print(f"landscape minimum {objective} {truth.score:g} at {len(truth.cells):,} locations "
              f"({truth.fraction:.2%} of feasible), most symmetric ({x:.3f}, {y:.3f}, {z:.3f}) "
              f"m: {reached}")
    if config["episode_end"] == "paper" and result.best_score > config["target"]:
        print(f"the episode-end target {objective} <= {config['target']:g} was never reached "
              "(episodes ended only by truncation)")
