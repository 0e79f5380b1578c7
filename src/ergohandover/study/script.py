"""The study's command line (``experiments/run_all.py``): the options for the configuration
(``--config``, ``--set KEY=VALUE``), the results folder and the engine (``--workers``,
``--engine``, ``--address``); a bad value is one line and exit code 2, before anything is
written."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from ..errors import ErgohandoverError
from .config import StudyConfig
from .engines import ENGINES, Engine

ROOT = Path(__file__).resolve().parents[3]
"""The checkout the study scripts run in (``experiments/``, ``results/``, ``paper_figs/``)."""
CONFIGS = ROOT / "experiments" / "configs"


def add_study_arguments(parser: argparse.ArgumentParser, results: Path | None = None) -> None:
    """The options every study script takes."""
    parser.add_argument("--config", type=Path, help="a study configuration: what differs from "
                        "the defaults of ergohandover.study.config (default: "
                        "experiments/configs/default.json)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="override one setting of the configuration, e.g. --set "
                        "learning.runs=20 or --set 'learning.wall_caps_s=[2,5]' (repeatable; "
                        "VALUE is JSON, else a string)")
    parser.add_argument("--results", type=Path, default=results,
                        help=f"results folder (default: {results or 'results/'})")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="processes, or CPUs of a local Ray instance (default: all cores)")
    parser.add_argument("--engine", choices=ENGINES, default="local",
                        help="where the parts' independent jobs run: this machine's process "
                        "pool (default) or Ray (learning runs, landscapes of workers and "
                        "variants, carries)")
    parser.add_argument("--address", help="with --engine ray: a running Ray cluster, auto or "
                        "HOST:PORT (default: start a local Ray instance of --workers CPUs)")


def study_from_args(args: argparse.Namespace, default: str = "default") -> tuple[StudyConfig,
                                                                                  Engine]:
    """The typed configuration and the engine of the parsed options (ConfigError if bad)."""
    engine = Engine(args.engine, args.workers, args.address)
    config = StudyConfig.load(args.config or CONFIGS / f"{default}.json", tuple(args.set))
    return config, engine


def duration(seconds: float) -> str:
    """``42 s`` or ``18.5 min``: a time or an estimate as a reader takes it in."""
    return f"{seconds:.0f} s" if seconds < 90 else f"{seconds / 60:.1f} min"


def fail(exc: ErgohandoverError) -> None:
    """One line on standard error and exit code 2."""
    print(f"{Path(sys.argv[0]).stem}: error: {exc}", file=sys.stderr)
    sys.exit(2)
