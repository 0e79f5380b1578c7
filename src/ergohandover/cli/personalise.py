"""``ergohandover personalise``: find one worker's own handover location, one handover at a time.

The command is thin: it turns flags into a grid, a worker, a prior, a searcher and an oracle,
and hands them to :mod:`ergohandover.search.session`, which proposes, records and saves.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

from ..envs.scores import OBJECTIVES
from ..errors import ConfigError
from ..io.csv_input import InputError
from ..study.population.config import PopulationConfig
from . import defaults
from .options import (
    add_evaluator_arguments,
    add_output_folder_argument,
    evaluator_from_args,
    grid_from_args,
    model,
    run_folder,
)
from .parser import given
from .personalise_outputs import report, write_outputs
from .values import angle_error, boundary, choice, number, output_file, rule, whole

DEFAULT_SEARCHER = "fitted-twin"
"""The searcher whose recommendation was most often a worker's true optimum in the
personalisation study with postures measured with 5° of error, after 10 handovers, in model
(results/personalise/measured_summary.csv picks it: its ``X+prior`` rows are this command's
``--searcher X``). It learns from every measured angle an answer carries (a posture row or a
captured frame) and from a score alone."""
DEFAULT_TRIALS = 25
"""One of the study's budgets (:class:`~ergohandover.study.config.PersonaliseConfig`), so the
study says how often that many handovers found a worker's own optimum."""
BOUNDARY: str = defaults.field_default(PopulationConfig, "boundary")
STEP: float = defaults.field_default(PopulationConfig, "step")
"""The personalisation study's grid: the population study's, on which every worker's optimum
(and so the prior) was found."""
ORACLES = ("twin", "ask", "file")
ANSWER_KINDS = ("scores", "pairwise")
PAIRWISE_SEARCHER = "pairwise"
"""The searcher told preferences (search/pairwise.py)."""
POLL_S = 1.0
PAUSED = 3
"""The exit code of a session that paused before its end because standard input ended: every
answer is saved and a rerun resumes (not 0: the session has no recommendation yet; not 130:
no signal stopped it)."""
RESOLUTION = 0.05
"""The smallest distance between proposals to a person [m]: a box is placed by hand to a few
centimetres, and two handovers a centimetre apart are the same handover to the worker."""
ASKED = "reba"
"""The score a person answering at the prompt gives unless --objective says otherwise."""
STATE = "state.json"
PROPOSAL = "proposal.csv"

DESCRIPTION = f"""\
Find one worker's own handover location in a few real handovers: a searcher proposes a location,
the score observed there is its answer, and the next proposal uses every answer so far. The
score is --objective's: with --oracle ask an ergonomist types it (or 'x' where the worker cannot
take the box, or a Posture CSV row to score); --oracle file reads 'TRIAL,ANSWER' lines that
another program appends to --answer-file; --oracle twin lets the worker's twin answer (a
demonstration). With --answers pairwise nobody gives a score: each handover is called better,
worse or same than the one before it. The searcher starts from the worker's expected optimum
(the population prior: stature and sex) unless --no-prior.
The state is saved after every answer (--state): a session stopped before its end resumes where
it stopped when the same command is run again (with --output or --state; without them, the
command names the folder to resume from). Standard input ending pauses it with exit code {PAUSED};
Ctrl-C and kill stop it with 130 and 143, every answer kept.
At the end: the recommended location, from the searcher's model (the fitted twin's: where it
expects the worker's optimum, with the probability it gives that and the score it expects there
against the prior's location, where a site hands over without searching; with pairwise answers,
the one the preference model prefers; any other searcher's: the tried location a model of its
answers expects lowest, never the lowest single reading), the trials
used and why the session ended, and how sure the recommendation is; trials.csv,
recommendation.csv and manifest.json are written into --output (default: a new
runs/personalise/<timestamp>/). See docs/personalise.md."""


ANGLE_ERROR = "5"
"""The answers' angle error a fitted twin assumes by default: 5° SD on every angle, the
personalisation study's headline answers."""


def add_parser(subparsers) -> None:
    from ..landscape.grid import BOUNDARY_NAMES

    parser = subparsers.add_parser(
        "personalise", help="find one worker's handover location with real handovers",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    answers = parser.add_argument_group("answers")
    answers.add_argument("--oracle", required=True, type=choice(ORACLES),
                         metavar="|".join(ORACLES), help="who answers each proposal: the "
                         "worker's twin, a person at the terminal, or --answer-file")
    answers.add_argument("--answers", type=choice(ANSWER_KINDS), metavar="|".join(ANSWER_KINDS),
                         help="what is answered: a score of each handover, or pairwise: which "
                         "of the last two handovers was better (better, worse, same) (default: "
                         "what --searcher is told; pairwise goes with --searcher pairwise, its "
                         "default)")
    answers.add_argument("--answer-file", type=output_file, metavar="CSV",
                         help="with --oracle file: the file of 'TRIAL,ANSWER' lines (it may not "
                         "exist yet); the pending proposal is written to proposal.csv in "
                         "--output")
    answers.add_argument("--answer-format", default="score", metavar="score|keypoints:FORMAT[:UP]",
                         help="what an answer of --oracle ask or file is: a score, x or a "
                         "posture row (default: score); or a frame a posture-capture program "
                         "measured: FORMAT's joints, x, y, z each in metres (FORMAT: h36m17, "
                         "coco17, mediapipe33, zed34, smpl24; UP: its up axis, default the "
                         "format's), scored as 'ergohandover score --keypoints' scores it")
    answers.add_argument("--angle-error", type=angle_error, default=ANGLE_ERROR, metavar="DEG|imu",
                         help="how the answers' angles were measured, for --searcher "
                         "fitted-twin's likelihood: every angle's SD in degrees, or imu (an "
                         "IMU suit: Schall et al. 2016's bias and SDs, errors correlated "
                         f"within a segment and between sides) (default: {ANGLE_ERROR}, the "
                         "study's headline answers)")
    answers.add_argument("--poll", type=number(0, None, "s", above=True), default=POLL_S,
                         metavar="S", help="with --oracle file: seconds between looks at "
                         f"--answer-file (default: {POLL_S:g})")
    search = parser.add_argument_group("search")
    names = registered_searchers()
    search.add_argument("--searcher", type=choice(names), metavar="|".join(names),
                        help="the ask/tell searcher (default: "
                        f"{DEFAULT_SEARCHER}, whose recommendation was most often a worker's "
                        "true optimum in the personalisation study with postures measured with "
                        f"5° of error; with --answers pairwise: {PAIRWISE_SEARCHER})")
    search.add_argument("--no-prior", action="store_true",
                        help="start without the population prior (default: start from it)")
    search.add_argument("--trials", type=whole(1), default=DEFAULT_TRIALS, metavar="N",
                        help="real handovers in all, those of a resumed session included "
                        f"(default: {DEFAULT_TRIALS})")
    search.add_argument("--target", type=number(0, None), metavar="SCORE",
                        help="end as soon as a score at or below SCORE is observed (default: "
                        "run the trials out)")
    search.add_argument("--seed", type=whole(0), default=defaults.SEED, metavar="K",
                        help=f"the searcher's seed, an integer >= 0 (default: {defaults.SEED})")
    search.add_argument("--objective", type=choice(OBJECTIVES), default=defaults.OBJECTIVE,
                        metavar="|".join(OBJECTIVES),
                        help="what an answered score is, the searcher minimises it (default: "
                        f"{defaults.OBJECTIVE}, the study's; with --oracle ask, {ASKED}: the "
                        "score an ergonomist reads)")
    search.add_argument("--boundary", type=boundary(BOUNDARY_NAMES), default=BOUNDARY,
                        metavar="|".join(BOUNDARY_NAMES) + "|X0,X1,Y0,Y1,Z0,Z1",
                        help=f"where locations may be proposed (default: {BOUNDARY}, the "
                        "personalisation study's)")
    search.add_argument("--step", type=number(0, None, "m", above=True), default=STEP,
                        metavar="S", help=f"grid step [m] (default: {STEP:g}, the "
                        "personalisation study's; with a person answering, --resolution's)")
    search.add_argument("--resolution", type=number(0, None, "m", above=True),
                        default=RESOLUTION, metavar="M",
                        help="with --oracle ask or file: the smallest distance between two "
                        "proposals [m], what a person can place a box to and tell apart; "
                        f"proposals lie on a grid of that step (default: {RESOLUTION:g})")
    add_evaluator_arguments(parser)
    files = parser.add_argument_group("files")
    files.add_argument("--state", type=output_file, metavar="FILE",
                       help=f"the session's state, saved after every answer and resumed from "
                       f"when it exists (default: --output's {STATE})")
    add_output_folder_argument(files, "result directory (created if needed; default: the "
                               "folder of --state if given, else a new "
                               "runs/personalise/<timestamp>/)")
    parser.set_defaults(run=run)


def check(args: argparse.Namespace) -> None:
    """What takes two flags: a one-line InputError naming them (and the searcher and answers
    each defaults to, from the other)."""
    from ..search.registry import entry

    flags = given(args)
    person = args.oracle in ("ask", "file")
    if "resolution" in flags and not person:
        raise InputError("--resolution cannot be used with --oracle twin (the twin answers "
                         "any grid; give --step)")
    if person and "step" in flags and "resolution" in flags:
        raise InputError(f"--step {args.step:g} and --resolution {args.resolution:g} both "
                         "given: give one (with a person answering, the grid's step is the "
                         "resolution)")
    if person and "step" not in flags:
        args.step = args.resolution
    if args.oracle == "file" and args.answer_file is None:
        raise InputError("--oracle file needs --answer-file CSV (the file answers are appended "
                         "to)")
    told = entry(args.searcher).answers if args.searcher else None
    if args.answers is None:
        args.answers = "pairwise" if told == "preferences" else "scores"
    if args.searcher is None:
        if args.no_prior and args.answers != "pairwise":
            raise InputError(f"--no-prior: the default searcher, {DEFAULT_SEARCHER}, starts from "
                             "the prior (give --searcher, e.g. cmaes, to search without it)")
        args.searcher = PAIRWISE_SEARCHER if args.answers == "pairwise" else DEFAULT_SEARCHER
    if args.oracle == "ask" and args.answers == "scores" and args.answer_format == "score" \
            and "objective" not in flags:  # a person types the score (not a frame's)
        args.objective = ASKED
    if (args.answers == "pairwise") != (entry(args.searcher).answers == "preferences"):
        raise InputError(f"--answers {args.answers}: --searcher {args.searcher} is told "
                         f"{entry(args.searcher).answers} (with --answers pairwise use "
                         f"--searcher {PAIRWISE_SEARCHER}; with scores, another searcher)")
    if args.answers == "pairwise":
        for flag, dest in (("--answer-format", "answer_format"), ("--target", "target")):
            if dest in flags:
                raise InputError(f"{flag} cannot be used with --answers pairwise (a preference "
                                 "is neither a score nor a frame)")
    if "angle_error" in flags and not entry(args.searcher).twins:
        raise InputError(f"--angle-error {args.angle_error} cannot be used with --searcher "
                         f"{args.searcher} (only a fitted twin weighs the answers' angles)")
    if "answer_format" in flags and args.oracle == "twin":
        raise InputError("--answer-format cannot be used with --oracle twin (only with --oracle "
                         "ask or file)")
    if args.answer_format != "score":
        from ..search.answers import frame_format

        try:
            frame_format(args.answer_format, args.objective)
        except ConfigError as exc:
            raise InputError(str(exc).replace(f"answer_format = {args.answer_format!r}",
                                              f"--answer-format {args.answer_format}")) from None
    for flag, dest in (("--answer-file", "answer_file"), ("--poll", "poll")):
        if dest in flags and args.oracle != "file":
            raise InputError(f"{flag} cannot be used with --oracle {args.oracle} (only with "
                             "--oracle file)")
    if args.answer_file == "-":
        raise InputError("--answer-file -: not a file (with standard input, use --oracle ask)")
    if args.state == "-":
        raise InputError("--state -: not a file (the state is read back on resume)")
    described = {"stature", "sex"} <= flags or "percentile" in flags
    if args.oracle != "twin" and not described:
        raise InputError(f"--oracle {args.oracle} needs the worker: give --stature M and --sex "
                         "female|male (or --percentile NAME)")


def registered_searchers() -> tuple[str, ...]:
    """The registry's ask/tell searchers (a ``+prior`` variant is this command's searcher with
    its default prior)."""
    from ..search.registry import names

    return names("searcher", variants=False)


def worker_prior(args: argparse.Namespace, evaluator):
    """The population model and the worker's prior from it (None, None with --no-prior, or for
    a searcher that takes no prior)."""
    from ..search.registry import entry

    if args.no_prior or entry(args.searcher).prior == "none":
        return None, None
    from ..search.prior import shipped_prior

    body = evaluator.body
    population = shipped_prior()
    if population.objective != args.objective:
        print(f"note: the prior predicts the {population.objective} optimum; it is the starting "
              f"point for {args.objective} too", file=sys.stderr)
    return population, model(population.predict, body.stature_m, body.sex)


def places(args: argparse.Namespace) -> tuple[Path | None, Path | None]:
    """The output folder and the state file the flags name (None, None: neither is named)."""
    if args.output is not None:
        output = Path(args.output)
        return output, Path(args.state) if args.state else output / STATE
    if args.state is not None:
        return Path(args.state).parent, Path(args.state)
    return None, None


SETTING_FLAGS = {"searcher": "--searcher", "seed": "--seed", "objective": "--objective",
                 "grid": "--boundary, --step", "prior": "--no-prior",
                 "evaluator.body": "the worker's flags", "evaluator.task": "the task flags",
                 "evaluator.solver": "--solver", "evaluator.trunk_reference": "--trunk-reference"}


def open_session(args, state: Path, settings: dict, searcher):
    """The session saved in ``state`` (or a new one there), ``searcher`` told its history; a
    state that is not this command's is refused naming the flag that differs."""
    from ..search.session import Session, StateError, StateMismatch

    named = f"--state {state}" if args.state else f"--output {args.output}"
    try:
        session = Session.open(state, settings)
        session.resume(searcher)
    except (StateError, ConfigError) as exc:  # ConfigError: a history the searcher disowns
        raise InputError(f"{named}: {exc}") from None
    except StateMismatch as exc:
        flag = next((f" ({f})" for k, f in SETTING_FLAGS.items() if exc.key.startswith(k)), "")
        raise InputError(f"{named}: its session was made with {exc.key} = {exc.old!r}, this "
                         f"command has {exc.new!r}{flag}: rerun that session's command to "
                         "resume it, or give another --state") from None
    return session


def build_oracle(args, grid, evaluator, reader, output: Path):
    from ..search.oracles import AskOracle, ComparingTwin, FileOracle, TwinOracle

    if args.oracle == "twin":
        twin = ComparingTwin if args.answers == "pairwise" else TwinOracle
        return twin(grid, evaluator, args.objective)
    if args.oracle == "ask":
        return AskOracle(reader)
    return FileOracle(Path(args.answer_file), reader, args.poll, output / PROPOSAL)


def resolve(args: argparse.Namespace):
    """The evaluator, grid, prior and searcher the flags describe, and the settings a state
    must match; every refusal is one line naming the flags."""
    from ..search import make
    from ..search.answers import SCORE_RANGES
    from ..search.registry import entry

    check(args)
    evaluator = evaluator_from_args(args)
    grid = grid_from_args(evaluator, args.boundary, args.step)
    if args.trials > grid.size:
        raise InputError(f"--trials {args.trials}: more than the grid's {grid.size} locations "
                         "(--boundary, --step)")
    lo, hi = SCORE_RANGES[args.objective]
    if args.target is not None and not lo <= args.target <= hi:
        raise InputError(f"--target {args.target:g}: outside {rule(lo, hi)}, the range of "
                         f"--objective {args.objective}")
    population, prior = worker_prior(args, evaluator)
    try:
        twins = None
        if entry(args.searcher).twins and prior is not None:
            from ..search.fitted_twin import named_error, survey_library

            twins = survey_library(evaluator, grid, args.objective, args.seed,
                                   error=named_error(args.angle_error))
        searcher = make(args.searcher, grid, args.seed, prior, twins=twins)
    except ConfigError as exc:
        raise InputError(f"--searcher {args.searcher}: {exc}") from None
    # The prior's model, not its prediction: the worker is in "evaluator", and a state read on
    # another machine must not differ in a prediction's last bit.
    settings = {"searcher": args.searcher, "seed": args.seed, "objective": args.objective,
                "evaluator": dataclasses.asdict(evaluator), "grid": dataclasses.asdict(grid),
                "prior": None if population is None else population.to_dict()}
    if args.answers == "pairwise":  # (a session of scores keeps an earlier version's settings)
        settings["answers"] = "pairwise"
    if twins is not None and args.angle_error != ANGLE_ERROR:  # (likewise)
        settings["angle_error"] = args.angle_error
    return evaluator, grid, prior, searcher, settings


def run(args: argparse.Namespace) -> int:
    from ..io.holder import hold

    started = time.perf_counter()
    evaluator, grid, prior, searcher, settings = resolve(args)
    output, state = places(args)
    new_folder = output is None
    if new_folder:  # only now, every flag checked: a folder of its own
        output = run_folder("personalise")
        state = output / STATE
    # One session at a time on a state (and its output folder): a second is refused before
    # it reads the state, so neither overwrites the other's answers.
    held, named = (state, f"--state {args.state}") if args.state else (
        output, f"--output {args.output}" if args.output else str(output))
    with hold(held, named, "wait for that session to end, or give another --output"):
        return converse(args, started, evaluator, grid, prior, searcher, settings, output,
                        state, new_folder)


def converse(args, started, evaluator, grid, prior, searcher, settings, output: Path,
             state: Path, new_folder: bool) -> int:
    """The session itself, its state held by this process: propose, hear, save, report."""
    from ..search.answers import AnswerReader, PreferenceReader
    from ..search.oracles import AnswersEnded, in_cm
    from ..search.registry import entry
    from ..search.session import run as run_session

    session = open_session(args, state, settings, searcher)
    task = evaluator.task
    reader = PreferenceReader() if args.answers == "pairwise" else AnswerReader(
        args.objective, evaluator.scoring, session.posture_header,
        None if args.answer_format == "score" else args.answer_format,
        {"load_kg": task.box_mass_kg, "coupling": float(task.coupling),
         "activity": float(task.activity)}, evaluator.body)
    oracle = build_oracle(args, grid, evaluator, reader, output)
    introduce(args, evaluator, grid, prior, session)
    resume = "the same command" + (f" with --output {output}" if new_folder else "")
    try:
        stopped = run_session(session, searcher, oracle, args.trials, args.target,
                              say=lambda text: print(text, flush=True))
    except AnswersEnded:
        print(f"personalise: standard input ended before trial {len(session.trials) + 1}'s "
              f"answer; {saved(session, resume)}", file=sys.stderr)
        tidy(output, session, new_folder)
        return PAUSED
    except KeyboardInterrupt as exc:
        tidy(output, session, new_folder)
        exc.kept = f"; {saved(session, resume)}"  # the stop's one line says it
        raise
    oracle.finish()
    if entry(args.searcher).twins:
        model = searcher.recommend()
        print(f"fitted twin: {searcher.twins.names[searcher.chosen]}", flush=True)
        print(f"its model recommends {in_cm(grid.point(model.cell))}: a {model.p_optimal:.0%} "
              "probability that it is this worker's optimum", flush=True)
        there, nothing = searcher.posterior.expected_scores(
            [model.cell, grid.nearest_cell(prior.location)])
        print(f"it expects {args.objective} {there:.1f} there against {nothing:.1f} at the "
              f"prior's location (no search): a gain of {nothing - there:+.1f}", flush=True)
    best = session.best(searcher)
    sure = session.uncertainty(best, searcher)
    report(args, session, best, stopped, sure)
    config = {**settings, "prior_location": None if prior is None else list(prior.location)}
    for path in write_outputs(args, session, best, stopped, output, config, started, sure):
        print(f"wrote {path}", file=sys.stderr)
    return 0


def saved(session, resume: str) -> str:
    """What a paused session kept, and how to resume it."""
    count = len(session.trials)
    if not count:
        return "no trial was answered, nothing is saved"
    return (f"{count} trial{'s' * (count != 1)} saved in {session.path}: rerun {resume} to "
            "resume")


def tidy(output: Path, session, new_folder: bool) -> None:
    """Remove the new output folder of a session stopped before its first answer."""
    if new_folder and not session.history and not any(output.iterdir()):
        output.rmdir()


def introduce(args, evaluator, grid, prior, session) -> None:
    """The session's settings on standard error, and where a resumed one resumes."""
    from ..search.oracles import in_cm

    body = evaluator.body
    start = "no prior" if prior is None else f"prior at {in_cm(prior.location)}"
    print(f"personalise: worker {body.stature_m:g} m, {body.sex}; {grid.describe()}; searcher "
          f"{args.searcher} (seed {args.seed}, {start}); {args.objective}; {args.trials} "
          f"trials; state {session.path}", file=sys.stderr)
    if session.history:
        print(f"personalise: resuming after trial {len(session.trials)}", file=sys.stderr)
