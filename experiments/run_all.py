"""Run the whole study and build every table and figure: python experiments/run_all.py

Parts, in order (each resumable: a finished part is reused from its manifest.json):
  landscape     the exhaustive sweep of the default worker (the paper's 3-hour evaluation)
  learning      Q-learning (two temperatures), DQN, a random walk, random sampling and
                hill-climbing on budgets matched to the paper's caps, on nine targets
                (configs/paper.json: the paper's own protocol, 10 runs x 2 wall-clock caps)
  baselines     the shortest-distance vs the learner's location from the paper's five starts
  ablations     human IK (ours vs PyBullet's)
  participants  the VR participant study, simulated with six workers of different sizes
  population    one-size vs personalised handover locations over a sampled workforce, swept
                on the local process pool or on Ray (--engine ray [--address auto|HOST:PORT])
  sensitivity   which modelling choices move the optimum: a landscape per variant
  validation    the twin beside published human data (angles, working heights, lifts)
  figures       results/tables.md and paper_figs/*.png, built only from results/

--only PART runs one part (repeatable) and redraws its figures; the figures part draws every
figure and writes results/tables.md. --quick runs every part on coarse grids and second-long
caps (a few minutes) into results/quick/ and paper_figs/quick/; it is what the smoke test runs.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HERE = Path(__file__).resolve().parent
PARTS = ("landscape", "learning", "baselines", "ablations", "participants", "population",
         "sensitivity", "validation", "figures")
ENGINE_PARTS = ("population",)  # the parts that run on --engine (the others: the local pool)
# Rough wall time of each part on a 2-core machine [s] (measured), for the estimate printed
# at the start; parts already finished are not counted. The learning part estimates itself
# from its configuration (study_learning.estimate_s).
ESTIMATE_S = {"default": {"landscape": 150, "learning": 140, "baselines": 270,
                          "ablations": 65, "participants": 85, "population": 180,
                          "sensitivity": 95, "validation": 5, "figures": 20},
              "quick": {"landscape": 5, "learning": 10, "baselines": 85, "ablations": 15,
                        "participants": 10, "population": 20, "sensitivity": 60,
                        "validation": 5, "figures": 20}}
PART_FIGURES = {"landscape": "fig_score_distribution", "learning": "fig_learning",
                "baselines": "fig_baselines", "participants": "fig_participants",
                "population": "fig_population", "sensitivity": "fig_sensitivity",
                "validation": "fig_validation"}
"""Each part's figure script (each reads that part's results only)."""
FIGURE_SCRIPTS = (*PART_FIGURES.values(), "make_tables")


def parse(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog="\n".join(__doc__.splitlines()[2:]))
    parser.add_argument("--quick", action="store_true",
                        help="coarse grids and short caps (minutes), into results/quick/")
    parser.add_argument("--only", choices=PARTS, action="append", metavar="PART",
                        help=f"run only this part (repeatable): {', '.join(PARTS)}")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="processes (default: all cores)")
    parser.add_argument("--force", action="store_true", help="rerun parts even if finished")
    parser.add_argument("--engine", choices=("local", "ray"), default="local",
                        help="where the population part sweeps its workers' landscapes: the "
                        "local process pool (default) or Ray")
    parser.add_argument("--address", help="with --engine ray: a running Ray cluster, auto or "
                        "HOST:PORT (default: start a local Ray instance of --workers CPUs)")
    parser.add_argument("--config", type=Path, help="a config JSON (default: "
                        "experiments/configs/default.json, or quick.json with --quick)")
    parser.add_argument("--results", type=Path, help="results folder (default: results/, or "
                        "results/quick/ with --quick)")
    parser.add_argument("--figures", type=Path, help="figures folder (default: paper_figs/, "
                        "or paper_figs/quick/ with --quick)")
    args = parser.parse_args(argv)
    if args.workers < 1:
        parser.error(f"--workers {args.workers}: must be at least 1")
    if args.address is not None and args.engine != "ray":
        parser.error(f"--address {args.address}: needs --engine ray")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse(argv)
    mode = "quick" if args.quick else "default"
    config_path = args.config or HERE / "configs" / f"{mode}.json"
    config = json.loads(config_path.read_text())
    results = args.results or ROOT / "results" / ("quick" if args.quick else "")
    figures = args.figures or ROOT / "paper_figs" / ("quick" if args.quick else "")
    parts = args.only or list(PARTS)
    from ergohandover.study.parts import is_done, part_config

    todo = [p for p in parts if p == "figures" or args.force
            or not is_done(results / p, part_config(config, p))]
    seconds = {p: part_estimate(p, mode, config, args.workers) for p in todo}
    estimate = sum(seconds.values())
    plan = (f"estimated {estimate / 60:.0f} min: "
            + ", ".join(f"{p} {s / 60:.1f}" for p, s in seconds.items()) if todo
            else "every part is finished already")
    print(f"run_all ({mode}, config {config_path.name}, {args.workers} workers): parts "
          f"{', '.join(parts)}; {plan}")
    start = time.perf_counter()
    from ergohandover.errors import ErgohandoverError

    try:
        run_parts(parts, config, results, figures, args)
    except ErgohandoverError as exc:  # a bad value: one line, exit code 2, no traceback
        print(f"run_all: error: {exc}", file=sys.stderr)
        return 2
    print(f"run_all done in {(time.perf_counter() - start) / 60:.1f} min "
          f"(estimated {estimate / 60:.0f} min)")
    return 0


def run_parts(parts: list[str], config: dict, results: Path, figures: Path,
              args: argparse.Namespace) -> None:
    for part in parts:
        t0 = time.perf_counter()
        print(f"== {part}")
        if part == "figures":
            build_figures(results, figures)
        else:
            module = importlib.import_module(f"study_{part}")
            engine = ({"engine": args.engine, "address": args.address}
                      if part in ENGINE_PARTS else {})
            module.run(config, results, args.workers, force=args.force, **engine)
            if "figures" not in parts and part in PART_FIGURES:  # --only PART: its figures
                build_figures(results, figures, (PART_FIGURES[part],))
        print(f"   {part}: {time.perf_counter() - t0:.0f} s")


def part_estimate(part: str, mode: str, config: dict, workers: int) -> float:
    """A part's rough wall time [s]: the learning part's from its own configuration (the
    paper's protocol alone is 35 min of wall-clock caps), the others' from ESTIMATE_S (measured
    on 2 cores)."""
    if part == "learning":
        return importlib.import_module("study_learning").estimate_s(config, workers)
    return ESTIMATE_S[mode][part]


def build_figures(results: Path, figures: Path, scripts: tuple[str, ...] = FIGURE_SCRIPTS) -> None:
    """Run analysis scripts (each reads results/ only; default: every one) against these
    folders."""
    env = {**os.environ, "ERGOHANDOVER_RESULTS": str(results),
           "ERGOHANDOVER_FIGURES": str(figures)}
    for script in scripts:
        subprocess.run([sys.executable, str(HERE / "analysis" / f"{script}.py")], env=env,
                       check=True)


if __name__ == "__main__":
    sys.path.insert(0, str(HERE))
    sys.exit(main())
