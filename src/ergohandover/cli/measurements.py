"""A person's own measurements on the command line: a few flags, or one row of survey columns.

``--elbow-height``, ``--arm-length`` and ``--shoulder-height`` give single landmarks in metres;
``--measurements FILE`` reads a one-row CSV whose columns are the ANSUR II survey's (the
public data files' names and units: millimetres, weight in tenths of a kilogram; the files'
other columns are ignored, so a row copied from them works, a column they lack is refused, and
their ``Gender`` column gives the sex unless ``--sex`` does). Whatever is not given is filled
in by the body model fitted to the survey, given what is.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pandas as pd

from ..io.csv_input import InputError
from .values import number

FLAGS = {"elbow_height": "elbow_height_m", "arm_length": "arm_length_m",
         "shoulder_height": "shoulder_height_m"}
"""Flag destination -> the body model's name."""

FLAG_HELP = {
    "elbow_height": "standing elbow height [m]: floor to the underside of the elbow, forearm "
                    "horizontal",
    "arm_length": "arm length [m]: shoulder (acromion) to wrist, arm hanging",
    "shoulder_height": "shoulder (acromial) height [m], standing",
}


def add_measurement_arguments(group) -> None:
    """The measurement flags, in the worker's argument group."""
    for dest, text in FLAG_HELP.items():
        group.add_argument(f"--{dest.replace('_', '-')}", type=number(0.0, None, "m", above=True),
                           metavar="M",
                           help=f"{text} (default: the body model's, given the rest)")
    group.add_argument("--measurements", type=Path, metavar="CSV",
                       help="one row of ANSUR II survey columns (mm, weightkg in 0.1 kg), e.g. "
                       "a row of the survey's public files: the worker's own measurements")
    group.add_argument("--proportions", choices=("ansur2", "drillis-contini"),
                       default="ansur2", help="ansur2: landmarks from the survey's body model "
                       "(default); drillis-contini: the fixed-ratio twin, every length a fixed "
                       "fraction of stature")


UNITS = (("metres", 1000.0), ("centimetres", 10.0), ("whole kilograms", 10.0))
"""Units a survey value may have been typed in, and the factor to the survey's own."""


def wrong_unit(name: str, column: str, number: float) -> str | None:
    """The unit ``number`` was evidently typed in when it is implausible in the survey's
    (millimetres; tenths of a kilogram for weight) but plausible in that unit, else None."""
    from ..twin.anthropometry import MASS_RANGE_KG, PLAUSIBLE_SDS, STATURE_RANGE_M
    from ..twin.body_model import SURVEY_SCALE, body_model

    fields = {"stature_m": STATURE_RANGE_M, "mass_kg": MASS_RANGE_KG}
    ranges = [fields[name]] if name in fields else [
        model.value_range(name, PLAUSIBLE_SDS) for model in body_model().values()]
    lo, hi = min(r[0] for r in ranges), max(r[1] for r in ranges)
    scale = SURVEY_SCALE[column]
    if lo <= number / scale <= hi:
        return None
    units = UNITS[2:] if column == "weightkg" else UNITS[:2]
    return next((unit for unit, factor in units if lo <= number * factor / scale <= hi), None)


def survey_measurements(row: dict, what: str = "the survey row") -> dict[str, float]:
    """The body model's measurements [m, kg] from survey columns and units; a value in
    another unit (metres, centimetres, whole kilograms) is refused naming its column."""
    from ..twin.body_model import MEASUREMENTS, SURVEY_SCALE

    out = {}
    for name, column in MEASUREMENTS.items():
        if column in row and row[column] is not None and not pd.isna(row[column]):
            value = row[column]
            try:
                number = float(value)
            except (TypeError, ValueError):
                raise InputError(f"{what}: {column} = {value!r} is not a number (survey "
                                 "units: mm, weightkg in 0.1 kg)") from None
            typed_in = wrong_unit(name, column, number)
            if typed_in is not None:
                unit = "tenths of a kilogram (85 kg is 850)" if column == "weightkg" else \
                    "millimetres (1.72 m is 1720)"
                raise InputError(f"{what}: {column} = {value!r} looks like {typed_in}; the "
                                 f"survey's columns are {unit}")
            out[name] = number / SURVEY_SCALE[column]
    return out


def check_columns(columns, what: str) -> None:
    """Refuse a column the survey's files do not have (a misspelling would drop the value
    silently), naming the closest survey column; the survey's other columns are ignored."""
    import difflib

    from .survey_columns import SURVEY_COLUMNS

    known = {c.lower(): c for c in SURVEY_COLUMNS}
    for column in columns:
        name = str(column).strip()
        if name.lower() in known:
            continue
        close = difflib.get_close_matches(name.lower(), list(known), n=1, cutoff=0.0)
        raise InputError(f"{what}: column '{name}' is not an ANSUR II survey column; the "
                         f"closest is '{known[close[0]]}'")


def read_survey_row(path: Path) -> tuple[dict[str, float], str | None]:
    """The measurements of a one-row survey CSV, and its sex if it has a ``Gender`` column."""
    from ..io.csv_input import check_header
    from ..twin.body_model import MEASUREMENTS

    what = f"--measurements {path}"
    try:
        header = path.read_bytes().decode("latin-1").partition("\n")[0]
        check_header(header, what)
        table = pd.read_csv(path, encoding="latin-1")
    except FileNotFoundError:
        raise InputError(f"--measurements {path}: no such file") from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        reason = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        raise InputError(f"--measurements {path}: not a CSV file ({reason})") from None
    if len(table) != 1:
        raise InputError(f"--measurements {path}: {len(table)} rows; expected one person's")
    check_columns(table.columns, what)
    row = table.iloc[0].to_dict()
    found = survey_measurements(row, what)
    if not found:
        raise InputError(f"--measurements {path}: no survey column found (expected some of "
                         f"{', '.join(sorted(MEASUREMENTS.values()))})")
    gender = str(row.get("Gender", "")).strip().lower()
    return found, (gender if gender in ("male", "female") else None)


def measured_body(args: argparse.Namespace, base, default_sex: str):
    """The worker the flags describe.

    ``base`` is the named percentile or manikin the user chose, its stature, mass and sex
    already overridden by ``--stature``, ``--mass``, ``--sex``: what no flag or measurement
    gives is its. Without one (``base`` None), what is not given is the body model's mean given
    what is: a 1.62 m woman gets the mass and proportions of 1.62 m women, not a percentile's.
    Sex: ``--sex``, else the survey row's, else ``base``'s, else ``default_sex``.
    """
    from ..twin.anthropometry import BodySpec, BodySpecError
    from ..twin.proportions import ORDER

    given: dict[str, float] = {}
    survey_sex = None
    if args.measurements is not None:
        given, survey_sex = read_survey_row(args.measurements)
    for dest, name in FLAGS.items():
        value = getattr(args, dest)
        if value is not None:
            given[name] = value
    landmarks = dict(given)
    for name, flag in (("stature_m", "stature"), ("mass_kg", "mass")):
        if getattr(args, flag) is not None:
            given[name] = getattr(args, flag)
    sex = args.sex or survey_sex or (base.sex if base is not None else default_sex)
    if args.proportions != "ansur2":
        if landmarks:
            raise InputError(f"--proportions {args.proportions} takes no measurements (its "
                             "lengths are fractions of stature)")
        sized = base if base is not None else BodySpec.from_measurements(given, sex)
        return BodySpec(sized.stature_m, sized.mass_kg, sex, proportions=args.proportions)
    if base is not None:
        if not landmarks and sex == base.sex:
            return base
        for name in ("stature_m", "mass_kg"):
            given.setdefault(name, getattr(base, name))
    # Landmarks that cannot be one body are refused as typed, before the model fills in
    # (and perhaps carries the contradiction into a stature no flag gave).
    typed = {**landmarks, **{k: v for k, v in given.items() if k == "stature_m"}}
    for lower, upper in ORDER:
        if lower in typed and upper in typed and not typed[lower] < typed[upper]:
            raise BodySpecError(f"{lower} = {typed[lower]:.3f} m is not below {upper} = "
                                f"{typed[upper]:.3f} m: the measurements do not fit one body")
    return BodySpec.from_measurements(given, sex)
