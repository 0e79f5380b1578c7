"""``ergohandover train``: search the handover grid with a learner or a baseline, under a cap."""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time
from pathlib import Path

from tqdm import tqdm

from ..io.csv_input import InputError
from ..landscape.cache import Landscape
from ..landscape.grid import DEFAULT_STEP, Grid, parse_boundary
from ..landscape.store import cached_landscape
from ..learning.agents import AGENTS, agent, run_agent
from ..learning.qlearning import TEMPERATURES
from .options import (
    add_evaluator_arguments,
    evaluator_from_args,
    run_folder,
    task_flags_given,
)

DESCRIPTION = """\
Search the grid of box locations for the lowest ergonomic score with tabular Q-learning (the
paper's: alpha 0.1, gamma 0.9, Q = 0, softmax with temperature 0.7; qlearning-adaptive: the
paper's text's adaptive temperature), DQN (stable-baselines3), a random walk (the learner's
moves and restarts, no learning), uniform random search or hill-climbing with random restarts,
until a wall-clock or step cap.
Scores come from --landscape (a landscape file), else from the landscape cache when the grid of
--boundary/--step for this worker was swept before (`ergohandover sweep`), else they are computed
online (memoised). Writes trace.csv (time_s, step, best score and
its x, y, z after every improvement), best_locations.csv (every location found at the best
score, the most symmetric first), q_table.npz (Q-learning: visited states only) or
dqn_model.zip, and manifest.json into --output (default: a new runs/train/<timestamp>/)."""


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "train", help="learn or search the best handover location under a time or step cap",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--agent", required=True, metavar="|".join(AGENTS),
                        help="the learner or baseline")
    caps = parser.add_argument_group("budget (give exactly one)")
    caps.add_argument("--time-cap", metavar="S", help="wall-clock cap [s] (paper: 120, 300)")
    caps.add_argument("--steps", metavar="N", help="step cap [env steps]; deterministic")
    parser.add_argument("--seed", default="0", metavar="K",
                        help="seed, an integer >= 0 (default: 0)")
    parser.add_argument("--objective", default="paper_postural",
                        metavar="paper_postural|reba|reba_ab|rula",
                        help="score to minimise (default: paper_postural, the paper's)")
    parser.add_argument("--temperature", default="fixed", metavar="fixed|adaptive",
                        help="with --agent qlearning: fixed 0.7 (the published code) or adaptive "
                        "(the paper's text; bounded 0.1-2.0), the same as --agent "
                        "qlearning-adaptive (default: fixed)")
    parser.add_argument("--target", default="4", metavar="E",
                        help="with --episode-end paper: the episode ends when the score is at "
                        "most E (default: 4, the paper's and, on the default grid, the twin's "
                        "minimum too)")
    parser.add_argument("--episode-end", default="paper", metavar="paper|none",
                        help="paper: at the target; none: only by truncation (default: paper)")
    parser.add_argument("--episode-steps", default="10000", metavar="N",
                        help="truncate episodes after N steps, then restart at a random cell "
                        "(default: 10000)")
    parser.add_argument("--landscape", type=Path, metavar="FILE",
                        help="read scores from this landscape file; its grid is used. Without "
                        "it: the landscape cache's for --boundary/--step if swept before, else "
                        "online")
    parser.add_argument("--boundary", metavar="body|paper-code|X0,X1,Y0,Y1,Z0,Z1",
                        help="grid boundary (default: paper-code, the published "
                        "learner's, so online and landscape runs solve the same problem)")
    parser.add_argument("--step", metavar="S",
                        help=f"online grid step [m] (default: {DEFAULT_STEP})")
    add_evaluator_arguments(parser, solver=False)
    parser.add_argument("--output", type=Path, metavar="DIR",
                        help="result directory (default: a new runs/train/<timestamp>/)")
    parser.set_defaults(run=run)


def _choice(name: str, value: str, allowed) -> str:
    if value not in allowed:
        raise InputError(f"{name} = {value!r} is not allowed (use {', '.join(allowed)})")
    return value


def _number(name: str, text: str | None, kind, lo: float, strict: bool = False):
    """``text`` as ``kind`` at least ``lo`` (above it if ``strict``); one-line InputError."""
    if text is None:
        return None
    rule = f"{'>' if strict else '>='} {lo:g}"
    try:
        value = kind(text)
    except ValueError:
        value = None
    if value is None or not math.isfinite(value) or value < lo or (strict and value == lo):
        kind_name = "an integer" if kind is int else "a number"
        raise InputError(f"{name} = {text!r} is outside the valid range ({kind_name} {rule})")
    return value


def parse(args: argparse.Namespace) -> dict:
    """Every argument checked, as a dict of typed values (the run's resolved config)."""
    from ..envs.handover_env import EPISODE_ENDS
    from ..envs.scores import OBJECTIVES

    if (args.time_cap is None) == (args.steps is None):
        raise InputError("give exactly one of --time-cap S or --steps N (got "
                         f"{'neither' if args.time_cap is None else 'both'})")
    name = _choice("agent", args.agent, AGENTS)
    if _choice("temperature", args.temperature, TEMPERATURES) == "adaptive":
        if agent(name).temperature is None:
            raise InputError(f"temperature = 'adaptive' is not allowed with agent = {name!r} "
                             "(Q-learning's only: use --agent qlearning)")
        name = "qlearning-adaptive"
    config = {
        "agent": name,
        "time_cap_s": _number("time-cap", args.time_cap, float, 0, strict=True),
        "steps": _number("steps", args.steps, int, 1),
        "seed": _number("seed", args.seed, int, 0),
        "objective": _choice("objective", args.objective, OBJECTIVES),
        "target": _number("target", args.target, float, 0),
        "episode_end": _choice("episode-end", args.episode_end, EPISODE_ENDS),
        "episode_steps": _number("episode-steps", args.episode_steps, int, 1),
        "landscape": args.landscape,
    }
    if args.landscape is not None:
        given = [f"--{f}" for f, v in (("boundary", args.boundary), ("step", args.step),
                                      ("percentile", args.percentile), ("stature", args.stature),
                                      ("mass", args.mass), ("sex", args.sex)) if v is not None]
        given += ["--trunk-reference"] * (args.trunk_reference != "vertical")
        given += task_flags_given(args)
        if given:
            raise InputError(f"{given[0]} cannot be used with --landscape (the landscape fixes "
                             "the grid, worker and task)")
        if not args.landscape.is_file():
            raise InputError(f"landscape = '{args.landscape}' is not an existing file")
    else:
        config["boundary"] = args.boundary or "paper-code"
        config["step"] = _number("step", args.step, float, 0, strict=True) or DEFAULT_STEP
    return config


def build_env(config: dict, args: argparse.Namespace):
    """The env and what it was built from (landscape or online evaluator and grid)."""
    from ..envs import HandoverEnv, LandscapeScores, OnlineScores

    if config["landscape"] is not None:
        landscape = Landscape.load(config["landscape"])
    else:  # the landscape cache holds this grid's landscape if it was swept before
        evaluator = evaluator_from_args(args)
        grid = Grid(parse_boundary(config["boundary"], evaluator.body, evaluator.task),
                    config["step"])
        landscape = cached_landscape(evaluator, grid)
    if landscape is not None:
        scores = LandscapeScores(landscape, config["objective"])
        source = {"landscape": str(landscape.path), "landscape_key": landscape.key}
    else:
        # Random search jumps anywhere: prefetching a cube of neighbours would be waste.
        scores = OnlineScores(grid, evaluator, config["objective"],
                              block=1 if config["agent"] == "random" else 4)
        source = {"evaluator": dataclasses.asdict(evaluator)}
    env = HandoverEnv(scores, observation=agent(config["agent"]).observation,
                      episode_end=config["episode_end"], target=config["target"])
    source["grid"] = dataclasses.asdict(scores.grid)
    return env, landscape, source


def _bar(config: dict) -> tqdm:
    if config["time_cap_s"] is not None:
        return tqdm(total=round(config["time_cap_s"], 1), unit="s", desc=config["agent"],
                    file=sys.stderr, disable=config["time_cap_s"] < 5,
                    bar_format="{l_bar}{bar}| {n:.0f}/{total:.0f} s {postfix}")
    slow = 10_000 if config["agent"] == "dqn" else 2_000_000
    return tqdm(total=config["steps"], unit="step", unit_scale=True, desc=config["agent"],
                file=sys.stderr, disable=config["steps"] < slow)


def run(args: argparse.Namespace) -> int:
    config = parse(args)
    if args.output is not None and args.output.exists() and not args.output.is_dir():
        raise InputError(f"output = '{args.output}' is a file (expected a directory)")
    started = time.perf_counter()
    env, landscape, source = build_env(config, args)
    with _bar(config) as bar:
        def progress(steps: int, elapsed: float) -> None:
            done = min(elapsed, bar.total) if config["time_cap_s"] else steps
            bar.set_postfix_str(f"{steps:,} steps", refresh=False)
            bar.update(done - bar.n)  # redraws at most every 0.1 s

        from ..learning.trace import Budget

        result, agent_config = run_agent(
            config["agent"], env, Budget(config["time_cap_s"], config["steps"]),
            config["seed"], config["episode_steps"], progress)
    output = args.output or run_folder("train")
    from ..learning.search import exhaustive
    from ..learning.trace import write_result

    truth = exhaustive(landscape, config["objective"]) if landscape is not None else None
    extra = {"steps_per_s": round(result.steps / max(result.elapsed_s, 1e-9), 1)}
    if truth is not None:
        extra.update(global_minimum=truth.score, reached_global_minimum=bool(
            result.best_score <= truth.score))
    resolved = {**{k: (str(v) if isinstance(v, Path) else v) for k, v in config.items()},
                **source, "agent_config": dataclasses.asdict(agent_config) if agent_config
                else None, "output": str(output)}
    paths = write_result(result, env.location, output, resolved,
                         seeds={"run": config["seed"]}, extra=extra)
    report(result, env, config, truth, time.perf_counter() - started)
    for path in paths:
        print(f"wrote {path}", file=sys.stderr)
    return 0


def report(result, env, config: dict, truth, wall_s: float) -> None:
    """The run's summary on standard output."""
    objective = config["objective"]
    if math.isinf(result.best_score):
        print(f"{result.agent} seed {config['seed']}: no feasible location seen in "
              f"{result.steps:,} steps")
        return
    cells = list(result.best_cells)
    from ..learning.trace import best_locations

    top = best_locations(result, env.location).iloc[0]
    time_s, step = result.first_reached
    print(f"{result.agent} seed {config['seed']}: best {objective} {result.best_score:g} at "
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
