"""Fit the twin's body model to the ANSUR II public data files and write its table of figures.

Usage: python experiments/tools/fit_body_model.py DATA_DIR [--output FILE]

DATA_DIR holds the survey's public files ``ANSUR_II_MALE_Public.csv`` and
``ANSUR_II_FEMALE_Public.csv`` (Gordon et al. 2014, NATICK/TR-15/007; a work of the U.S.
Government; the files are published by the U.S. Army and mirrored in several public
repositories). Per sex, the script writes the number of people, and the mean, SD and Pearson
correlations of the measurements that size the twin (``MEASUREMENTS`` in
:mod:`ergohandover.twin.body_model`), in metres and kilograms. The default output is the table
the package ships, ``src/ergohandover/twin/ansur2_body_model.json``; the data files themselves
are never part of the package.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from ergohandover.io.atomic import atomic_write
from ergohandover.twin.body_model import MEASUREMENTS, SURVEY_SCALE, TABLE_PATH

FILES = {"male": "ANSUR_II_MALE_Public.csv", "female": "ANSUR_II_FEMALE_Public.csv"}
SOURCE = ("Gordon CC, Blackwell CL, Bradtmiller B, Parham JL, Barrientos P, Paquette SP, Corner "
          "BD, Carson JM, Venezia JC, Rockwell BM, Mucher M, Kristensen S (2014). 2012 "
          "Anthropometric Survey of U.S. Army Personnel: Methods and Summary Statistics. "
          "NATICK/TR-15/007. U.S. Army Natick Soldier Research, Development and Engineering "
          "Center; public data files ANSUR_II_MALE_Public.csv and ANSUR_II_FEMALE_Public.csv")


def survey_table(path: Path) -> pd.DataFrame:
    """The model's measurements of one data file, in metres and kilograms."""
    if not path.is_file():
        raise SystemExit(f"fit_body_model: {path} does not exist (expected the survey's public "
                         "data file)")
    table = pd.read_csv(path, encoding="latin-1")
    missing = [c for c in MEASUREMENTS.values() if c not in table.columns]
    if missing:
        raise SystemExit(f"fit_body_model: {path} has no column {missing[0]!r}")
    columns = list(MEASUREMENTS.values())
    return table[columns].astype(float) / np.array([SURVEY_SCALE[c] for c in columns])


def fit(table: pd.DataFrame) -> dict:
    """Count, means, SDs and correlations of one sex, rounded to the survey's resolution."""
    return {"n": len(table),
            "mean": [round(float(v), 5) for v in table.mean()],
            "sd": [round(float(v), 5) for v in table.std(ddof=1)],
            "correlation": [[round(float(v), 4) for v in row]
                            for row in np.corrcoef(table.to_numpy().T)]}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 1)[1])
    parser.add_argument("data", type=Path, help="folder with the two ANSUR II public files")
    parser.add_argument("--output", type=Path, default=TABLE_PATH,
                        help=f"the table to write (default {TABLE_PATH.name} in the package)")
    args = parser.parse_args(argv)
    try:
        sexes = {sex: fit(survey_table(args.data / name)) for sex, name in FILES.items()}
    except SystemExit as error:
        print(error, file=sys.stderr)
        return 2
    document = {"source": SOURCE, "units": "metres; mass_kg in kilograms",
                "measurements": {name: column for name, column in MEASUREMENTS.items()},
                "sexes": sexes}
    text = json.dumps(document, indent=1) + "\n"
    atomic_write(args.output, lambda handle: handle.write(text))
    print(f"wrote {args.output}: " + ", ".join(f"{s} n = {v['n']}" for s, v in sexes.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
