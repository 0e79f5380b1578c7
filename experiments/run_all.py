"""Run the whole study and build every table and figure: python experiments/run_all.py

Parts, in order (each resumable: a finished part is reused from its manifest.json):
  landscape     the exhaustive sweep of the default worker (the paper's 3-hour evaluation)
  learning      Q-learning (two temperatures), DQN, a random walk, random sampling and
                hill-climbing on budgets matched to the paper's caps, on nine targets
                (configs/paper.json: the paper's own protocol, 10 runs x 2 wall-clock caps)
  baselines     the shortest-distance vs the learner's location from the paper's five starts
  ablations     human IK (ours vs PyBullet's)
  participants  the VR participant study, simulated with six workers of different sizes
  sensitivity   which modelling choices move the optimum: a landscape per variant
  validation    the twin beside published human data (angles, working heights, lifts)
  figures       results/tables.md and paper_figs/*.png, built only from results/

--quick runs every part on coarse grids and second-long caps (a few minutes) into
results/quick/ and paper_figs/quick/; it is what the smoke test runs.
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
PARTS = ("landscape", "learning", "baselines", "ablations", "participants", "sensitivity",
         "validation", "figures")
# Rough wall time of each part on a 2-core machine [s] (measured), for the estimate printed
# at the start; parts already finished are not counted. The learning part estimates itself
# from its configuration (study_learning.estimate_s).
ESTIMATE_S = {"default": {"landscape": 150, "learning": 140, "baselines": 270,
                          "ablations": 65, "participants": 85, "sensitivity": 95,
                          "validation": 5, "figures": 15},
              "quick": {"landscape": 5, "learning": 10, "baselines": 85, "ablations": 15,
                        "participants": 10, "sensitivity": 60, "validation": 5,
                        "figures": 15}}
FIGURE_SCRIPTS = ("fig_score_distribution", "fig_learning", "fig_baselines",
                  "fig_participants", "fig_sensitivity", "fig_validation", "make_tables")


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
    parser.add_argument("--config", type=Path, help="a config JSON (default: "
                        "experiments/configs/default.json, or quick.json with --quick)")
    parser.add_argument("--results", type=Path, help="results folder (default: results/, or "
                        "results/quick/ with --quick)")
    parser.add_argument("--figures", type=Path, help="figures folder (default: paper_figs/, "
                        "or paper_figs/quick/ with --quick)")
    args = parser.parse_args(argv)
    if args.workers < 1:
        parser.error(f"--workers {args.workers}: must be at least 1")
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
    for part in parts:
        t0 = time.perf_counter()
        print(f"== {part}")
        if part == "figures":
            build_figures(results, figures)
        else:
            module = importlib.import_module(f"study_{part}")
            module.run(config, results, args.workers, force=args.force)
        print(f"   {part}: {time.perf_counter() - t0:.0f} s")
    print(f"run_all done in {(time.perf_counter() - start) / 60:.1f} min "
          f"(estimated {estimate / 60:.0f} min)")
    return 0


def part_estimate(part: str, mode: str, config: dict, workers: int) -> float:
    """A part's rough wall time [s]: the learning part's from its own configuration (the
    paper's protocol alone is 35 min of wall-clock caps), the others' from ESTIMATE_S (measured
    on 2 cores)."""
    if part == "learning":
        return importlib.import_module("study_learning").estimate_s(config, workers)
    return ESTIMATE_S[mode][part]


def build_figures(results: Path, figures: Path) -> None:
    """Run every analysis script (each reads results/ only) against these folders."""
    env = {**os.environ, "ERGOHANDOVER_RESULTS": str(results),
           "ERGOHANDOVER_FIGURES": str(figures)}
    for script in FIGURE_SCRIPTS:
        subprocess.run([sys.executable, str(HERE / "analysis" / f"{script}.py")], env=env,
                       check=True)


if __name__ == "__main__":
    sys.path.insert(0, str(HERE))
    sys.exit(main())
