"""``ergohandover score``: score a table of postures with REBA, RULA and the paper's score."""

from __future__ import annotations

import argparse
import sys
import textwrap

import pandas as pd

from ..ergonomics import SCORE_COLUMNS, ScoringSettings, score_postures
from ..ergonomics.posture import COLUMNS
from ..io.atomic import atomic_write_csv
from ..io.posture_csv import read_postures
from .options import add_dataclass_arguments, dataclass_from_args, run_folder, writable
from .values import output_file


def optional_columns() -> str:
    """The optional Posture columns grouped by the value they take when absent."""
    by_default: dict[str, list[str]] = {}
    for column in COLUMNS:
        if column.default is not None:
            by_default.setdefault(f"{column.default:g}", []).append(column.name)
        elif column.same_as is not None:
            by_default.setdefault(f"as {column.same_as}", []).append(column.name)
    return "; ".join(f"{', '.join(names)} {value}" for value, names in by_default.items())


DESCRIPTION = f"""\
Score postures with REBA (Hignett & McAtamney 2000), RULA (McAtamney & Corlett 1993) and the
paper's additive postural score. Reads a Posture CSV (one posture per row, angles in degrees,
flexion +; its columns: docs/architecture.md, "File contracts"; an example: docs/report.md,
"Scoring postures"); writes its columns followed by every score column.
{textwrap.fill(f"Optional columns default: {optional_columns()}.", 96)}"""


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "score", help="score a Posture CSV with REBA, RULA and the paper's score",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--input", required=True, metavar="CSV",
                        help="Posture CSV to read, or - for standard input")
    parser.add_argument("--output", type=output_file, metavar="CSV",
                        help="scores CSV to write (atomically; its folder is created if "
                        "needed), or - for standard output (default: "
                        "runs/score/<timestamp>/scores.csv)")
    add_dataclass_arguments(parser, ScoringSettings, "scoring settings (what REBA/RULA leave "
                            "open)")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    settings = dataclass_from_args(ScoringSettings, args)
    name = "standard input" if args.input == "-" else args.input
    text, posture = read_postures(args.input, what=name)
    scores = pd.DataFrame(score_postures(posture, settings))
    passthrough = text.drop(columns=[c for c in text.columns if c in SCORE_COLUMNS])
    table = pd.concat([passthrough, scores], axis=1)
    output = args.output or str(run_folder("score") / "scores.csv")
    if output == "-":
        table.to_csv(sys.stdout, index=False)
    else:
        atomic_write_csv(table, writable(output))
        print(f"scored {len(table)} postures -> {output}", file=sys.stderr)
    return 0
