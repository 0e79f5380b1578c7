"""Run the whole study and build every table and figure: python experiments/run_all.py

A part is finished when its results/<part>/manifest.json matches its configuration and the
twin's code: a fresh clone reuses every committed part and only rebuilds the figures and
tables (half a minute); --force recomputes every part (the README gives the committed run's
time on 2 cores; a run prints its estimate first) but reuses the landscapes this twin already
has in the cache ($ERGOHANDOVER_CACHE; empty it to time a run from scratch); an interrupted
run resumes at the first unfinished part. One run at a time holds a results folder: a second
on the same --results is refused in one line naming the first.

Parts, in order:
  landscape     the exhaustive sweep of the default worker (the paper's 3-hour evaluation)
  learning      Q-learning (two temperatures), DQN, a random walk, random sampling and
                hill-climbing in paired runs on the paper's caps at three rates, nine targets
  baselines     the shortest-distance vs the learner's location from the paper's five starts
  ablations     human IK (the twin's whole-body solver vs PyBullet's)
  participants  the VR participant study, simulated with six workers of different sizes
  population    one-size vs personalised handover locations over a sampled workforce
  sensitivity   which modelling choices move the optimum: a landscape per variant
  validation    the twin beside published human data (angles, working heights, lifts)
  robustness    the recommendation under posture-measurement error and a wrong model
  stance        the headline comparison for a worker who may step toward the box
  personalise   how many handovers each searcher needs to find one worker's own optimum
  capture       how well each keypoint format measures the twin, and its scores with
                published angle errors
  people        the twin beside 957 measured handovers: where people received, its posture
                prediction, its recommendation against them, a fit of its weights held out
  manikins      the four standard manikins at the robustness part's headline locations
  accommodation 1,000 workers: where REBA and RULA stay low for most of a workforce
  figures       results/tables.md and paper_figs/*.png, built only from results/

Configurations (experiments/configs/, each what differs from the defaults in the
questions' config.py files; --show-config prints the resolved one):
  default.json  the study (the default)
  quick.json    coarse grids and second-long caps, into results/quick/ (--quick; minutes)
  paper.json    the paper's own protocol: 10 Q-learning runs at 2 and 10 at 5 minutes of wall
                clock with its episode end, and DQN at the same caps: 40 capped runs, two at a
                time on 2 cores, so 70 minutes of learning on top of the other parts; give it
                --results of its own (its figures go there too)
  population_1000.json  a workforce of 1,000 (for Ray: --only population --engine ray)
  personalise_full.json  every searcher further, Bayesian optimisation also from scratch
                (hours on 2 cores: --only personalise, on Ray)

Each part is a study question (src/ergohandover/study/<part>/) whose registry entry
(ergohandover.study.registry) declares the parts it needs: --only PART (repeatable) runs it
after every part it needs (each reused when finished; --force reruns only the named ones) and
redraws its figures. Each part prints its time against its declared budget.
--engine ray [--address ...] runs every part's independent jobs (learning runs, the
landscapes of workers and variants, the robot's carries) on Ray, with the same results.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import subprocess
import sys
import time
from pathlib import Path

from ergohandover.errors import ErgohandoverError
from ergohandover.executor import clean_stop
from ergohandover.io.atomic import OutputError, check_writable
from ergohandover.io.holder import hold
from ergohandover.study.registry import PARTS, QUESTIONS, part, question, run_order
from ergohandover.study.resume import is_done
from ergohandover.study.script import add_study_arguments, duration, fail, study_from_args

ROOT = Path(__file__).resolve().parents[1]
HERE = Path(__file__).resolve().parent
STEPS = (*PARTS, "figures")
COMMITTED = {"default": ROOT / "results", "quick": ROOT / "results" / "quick"}
"""Where each mode's last run left its manifests: a part's estimate is its time there when the
results folder being written has none of its own."""
PART_FIGURES = {q.name: q.figure for q in QUESTIONS if q.figure}
"""Each part's figure script (each reads that part's results only)."""
FIGURE_SCRIPTS = (*PART_FIGURES.values(), "make_tables")


def parse(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog="\n".join(__doc__.splitlines()[2:]))
    parser.add_argument("--quick", action="store_true",
                        help="configs/quick.json into results/quick/ and paper_figs/quick/")
    parser.add_argument("--only", choices=STEPS, action="append", metavar="PART",
                        help=f"run only this part (repeatable): {', '.join(STEPS)}")
    parser.add_argument("--force", action="store_true", help="rerun parts even if finished")
    parser.add_argument("--figures", type=Path, help="figures folder (default: paper_figs/, "
                        "paper_figs/quick/ with --quick, or RESULTS/figures with --results)")
    parser.add_argument("--show-config", action="store_true",
                        help="print the resolved configuration as JSON and stop")
    add_study_arguments(parser)
    args = parser.parse_args(argv)
    if args.workers < 1:
        parser.error(f"--workers {args.workers}: must be at least 1")
    if args.address is not None and args.engine != "ray":
        parser.error(f"--address {args.address}: needs --engine ray")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse(argv)
    mode = "quick" if args.quick else "default"
    try:
        config, engine = study_from_args(args, mode)
    except ErgohandoverError as exc:  # a bad value: one line, exit code 2, nothing written
        fail(exc)
    if args.show_config:
        print(json.dumps(dataclasses.asdict(config), indent=2))
        return 0
    results = args.results or ROOT / "results" / ("quick" if args.quick else "")
    # A run into a results folder of its own keeps its figures beside it, never in paper_figs/.
    figures = args.figures or (args.results / "figures" if args.results else
                               ROOT / "paper_figs" / ("quick" if args.quick else ""))
    for flag, folder in (("--results", results), ("--figures", figures)):
        try:  # before any part runs: a folder nothing can be written to is one line
            check_writable(folder, folder=True)
        except OutputError as exc:
            fail(OutputError(f"{flag} {exc}"))
    try:  # one run at a time on a results folder: a second is refused before it reads it
        with hold(results, f"--results {results}", "wait for that run to end, or give "
                  "another --results"):
            return run_study(args, config, engine, results, figures, mode)
    except ErgohandoverError as exc:
        fail(exc)


def run_study(args, config, engine, results: Path, figures: Path, mode: str) -> int:
    """Run what --only names (every part by default) into ``results``, held by this run."""
    # What --only names, with every question it needs (reused when finished), in run order.
    named = args.only or list(STEPS)
    steps = [*run_order([p for p in named if p != "figures"]),
             *(["figures"] if "figures" in named else [])]
    forced = {p for p in named if args.force}
    todo = [p for p in steps if p == "figures" or p in forced
            or not is_done(results / p, config.part_inputs(p))]
    found = {p: estimate(p, results, mode, config, engine.workers) for p in todo}
    seconds = {p: s for p, s in found.items() if s is not None}
    total = sum(seconds.values())
    unmeasured = [p for p, s in found.items() if s is None]
    known = ", ".join(f"{p} {duration(s)}" for p, s in seconds.items())
    plan = ("; ".join(filter(None, (f"estimated {duration(total)}: {known}" if known else "",
                                    f"not measured yet: {', '.join(unmeasured)}" if unmeasured
                                    else "")))
            if todo else "every part is finished already")
    source = args.config.name if args.config else f"{mode}.json"
    print(f"run_all ({mode}, config {source}, {engine.name} engine, {engine.workers} workers): "
          f"parts {', '.join(steps)}; {plan}")
    start = time.perf_counter()
    try:
        with clean_stop(resumes=True), engine.session():
            run_steps(steps, config, results, figures, engine, forced,
                      redraw=set(args.only or ()))
    except ErgohandoverError as exc:
        fail(exc)
    estimated = f" (estimated {duration(total)})" if seconds else ""
    print(f"run_all done in {duration(time.perf_counter() - start)}{estimated}")
    return 0


def run_steps(steps: list[str], config, results: Path, figures: Path, engine,
              forced: set[str], redraw: set[str] = frozenset()) -> None:
    """Run each step in order (a finished part is reused unless it is in ``forced``); each part
    in ``redraw`` (those --only names) redraws its own figures."""
    for step in steps:
        t0 = time.perf_counter()
        print(f"== {step}")
        ran = True
        if step == "figures":
            build_figures(results, figures)
        else:
            ran = part(step).run(config, results, engine, force=step in forced)
            if step in redraw and "figures" not in steps and step in PART_FIGURES:
                build_figures(results, figures, (PART_FIGURES[step],))
        took = duration(time.perf_counter() - t0)
        if step == "figures":
            print(f"   {step}: {took}")
        else:  # a part's time against its declared budget (a reused part took none)
            print(f"   {step}: {took} of its {duration(question(step).budget_s)} budget"
                  if ran else f"   {step}: reused")


def estimate(step: str, results: Path, mode: str, config, workers: int) -> float | None:
    """A part's wall time [s] as it was last measured: the time in its manifest in ``results``,
    else in the mode's committed results (:data:`COMMITTED`); the learning part's from its own
    configuration's runs at the speeds its last runs had (a configuration's wall-clock caps
    alone can be an hour); None for what was never measured here (the figures, a part never
    run)."""
    for folder in dict.fromkeys((results, COMMITTED[mode])):
        if step == "learning":
            found = part("learning").estimate_s(config, workers, folder / step)
            if found is not None:
                return found
            continue
        manifest = folder / step / "manifest.json"
        if manifest.is_file():
            return float(json.loads(manifest.read_text())["wall_time_s"])
    return None


def build_figures(results: Path, figures: Path, scripts: tuple[str, ...] = FIGURE_SCRIPTS) -> None:
    """Run analysis scripts (each reads results/ only; default: every one) against these
    folders."""
    env = {**os.environ, "ERGOHANDOVER_RESULTS": str(results),
           "ERGOHANDOVER_FIGURES": str(figures)}
    for script in scripts:
        subprocess.run([sys.executable, str(HERE / "analysis" / f"{script}.py")], env=env,
                       check=True)


if __name__ == "__main__":
    sys.exit(main())
