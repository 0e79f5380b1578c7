"""Fit the population prior (a worker's optimum from stature and sex) and write it.

Usage: python experiments/tools/fit_population_prior.py [WORKERS_CSV] [--output FILE]

WORKERS_CSV is the population study's ``workers.csv`` (default: the committed
``results/population/workers.csv``); the default output is the model the package ships,
``src/ergohandover/search/population_prior.json``, which ``ergohandover personalise`` reads
when it is given a worker's stature and sex. ``tests/test_population_prior.py`` keeps the
shipped file equal to the fit of the committed results.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import pandas as pd

from ergohandover.io.atomic import atomic_write
from ergohandover.search.prior import SHIPPED, PopulationPrior

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_INPUT = ROOT / "results" / "population" / "workers.csv"
DEFAULT_OUTPUT = ROOT / "src" / "ergohandover" / "learning" / SHIPPED


def prior_document(workers_csv: Path) -> dict:
    """The fitted model with its source."""
    model = PopulationPrior.fit(pd.read_csv(workers_csv))
    shown = workers_csv.relative_to(ROOT) if workers_csv.is_relative_to(ROOT) else workers_csv
    return {"source": f"the population study's workers and their own optima ({shown}); least "
                      "squares per axis on stature and sex, residual SD per axis",
            "model": model.to_dict()}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("workers", nargs="?", type=Path, default=DEFAULT_INPUT,
                        help=f"the population's workers.csv (default: {DEFAULT_INPUT})")
    parser.add_argument("--output", type=Path, default=DEFAULT_OUTPUT,
                        help=f"where to write the model (default: {DEFAULT_OUTPUT})")
    args = parser.parse_args(argv)
    if not args.workers.is_file():
        print(f"fit_population_prior: {args.workers} does not exist", file=sys.stderr)
        return 2
    document = prior_document(args.workers.resolve())
    text = json.dumps(document, indent=1) + "\n"
    atomic_write(args.output, lambda handle: handle.write(text))
    model = document["model"]
    print(f"fitted on {model['n_workers']} workers; residual SD (x, y, z) "
          f"{', '.join(f'{v * 100:.1f}' for v in model['residual_sd_m'])} cm -> {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
