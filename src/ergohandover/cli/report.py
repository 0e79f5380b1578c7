"""``ergohandover report``: one printable page per handover location for a worker or manikin."""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

from ..io.atomic import atomic_write_csv, nearest_existing
from ..io.csv_input import InputError
from ..study.script import ROOT
from .options import (
    add_evaluator_arguments,
    add_lift_arguments,
    add_shift_arguments,
    evaluator_from_args,
    lift_from_args,
    run_folder,
    shift_from_args,
)
from .values import BadValue, beyond_reach, output_folder

RESULTS = ROOT / "results"
"""The study's results in the checkout, wherever the command runs from."""
DESCRIPTION = """\
Write a one-page report per handover location — what a practitioner files: the twin holding
the box there (its picture), REBA, RULA, OWAS and the paper's score with their items, the revised
NIOSH lifting equation for a lift from there to --lift-destination, the static L5/S1 load and
strength, a shift of such handovers (--rate, --hold, --shift-hours: each joint's capacity at the
shift's end, the low back's daily dose), and the share of the study's workforce the location
suits (results/accommodation).
Writes report.html (one page per location, printable), report.csv (every number on the pages,
as shown) and, with --pdf, report.pdf printed by headless Chromium. docs/workload.md."""


def location(text: str) -> tuple[float, float, float]:
    """``X,Y,Z`` in metres, worker frame."""
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != 3 or not all(np.isfinite(values)):
        raise BadValue(text, "expected X,Y,Z: three finite coordinates in metres (worker "
                       "frame: x right, y up, z forward)")
    far = beyond_reach(values)
    if far:
        raise BadValue(text, far)
    return values


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "report", help="a printable one-page report per handover location",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--location", type=location, action="append", metavar="X,Y,Z",
                       help="a box location [m], worker frame; repeatable")
    where.add_argument("--headline", action="store_true",
                       help="every headline location of the study (results/robustness/"
                       "locations.csv)")
    parser.add_argument("--results", type=Path, default=RESULTS, metavar="DIR",
                        help="the study's results, for --headline and the workforce's share "
                        "(default: results/ of the checkout, from any working directory)")
    parser.add_argument("--output", type=output_folder, metavar="DIR",
                        help="folder to write into (default: runs/report/<timestamp>/)")
    parser.add_argument("--pdf", action="store_true",
                        help="also print report.pdf with headless Chromium")
    add_evaluator_arguments(parser)
    add_lift_arguments(parser)
    add_shift_arguments(parser)
    parser.set_defaults(run=run)


def named_locations(args: argparse.Namespace) -> pd.DataFrame:
    """The locations to report: name, x, y, z."""
    if not args.headline:
        return pd.DataFrame([(f"location {k + 1}", *p) for k, p in enumerate(args.location)],
                            columns=["location", "x", "y", "z"])
    path = args.results / "robustness" / "locations.csv"
    if not path.is_file():
        raise InputError(f"--headline: {path} does not exist (run the study, or give "
                         "--location X,Y,Z)")
    named = pd.read_csv(path)
    return named[["location", "x", "y", "z"]].drop_duplicates("location").reset_index(drop=True)


def workforce_share(results: Path, named: pd.DataFrame) -> tuple[pd.DataFrame, list[str]]:
    """The accommodation part's shares at each location: its own row for a headline location,
    else the nearest point of its grid (none beyond the grid, and ``workforce_note`` says
    why); and what the figures are."""
    columns = ["exact_share", "exact_low", "exact_high", "measured_share", "measured_low",
               "measured_high"]
    folder = results / "accommodation"
    empty = pd.DataFrame(np.nan, index=named.index, columns=columns)
    if not (folder / "cells.csv").is_file():
        why = f"{folder} holds no results of the study's workforce"
        return empty.assign(workforce_note=why), [f"No workforce share: {why}."]
    cells, at = pd.read_csv(folder / "cells.csv"), pd.read_csv(folder / "locations.csv")
    workers = int(at["workers"].iloc[0])
    xyz = cells[["x", "y", "z"]].to_numpy(float)
    step = float(np.min(np.diff(np.unique(xyz[:, 0]))))
    out = empty.assign(workforce_note="")
    for i, row in named.iterrows():
        point = row[["x", "y", "z"]].to_numpy(float)
        same = np.all(np.isclose(at[["x", "y", "z"]].to_numpy(float), point, atol=1e-6), axis=1)
        if same.any():
            out.loc[i, columns] = at.loc[np.flatnonzero(same)[0], columns].to_numpy(float)
            continue
        distance = np.linalg.norm(xyz - point, axis=1)
        if distance.min() <= step * np.sqrt(3) / 2:
            out.loc[i, columns] = cells.loc[int(np.argmin(distance)), columns].to_numpy(float)
        else:
            out.loc[i, "workforce_note"] = (
                f"beyond the study's {step * 100:g} cm grid of the workforce (its nearest point "
                f"is {100 * distance.min():.0f} cm away), where no share was computed")
    zone = pd.read_csv(folder / "zone.csv")
    limits = zone.iloc[0]
    return out, [f"Workforce: {workers} workers drawn from the ANSUR II body model; suited = "
                 f"REBA and RULA within the study's limits, error-free and as measured "
                 f"(IMU error model); a location off the study's headline list takes the "
                 f"nearest point of its {step * 100:g} cm grid (share {limits['share']:g} "
                 "zone: docs/workload.md)."]


def run(args: argparse.Namespace) -> int:
    from ..scene.render import render_points
    from ..twin.evaluate import EVALUATION_COLUMNS, evaluate
    from ..viewer.chromium import chromium, print_pdf
    from ..viewer.report_page import PAGE_COLUMNS, report_page, shown
    from ..workload import Levers, shift_table, workload_table
    from ..workload.flags import LIFTING_INDEX_SCOPE, flag_column, flags

    # Every check before any work: what to report, on whom, and that the PDF can be printed.
    evaluator = evaluator_from_args(args)
    lift = lift_from_args(args)
    plan = shift_from_args(args)
    named = named_locations(args)
    if args.pdf:
        chromium()
    output = args.output or run_folder("report")
    points = named[["x", "y", "z"]].to_numpy(float)
    table = evaluate(points, evaluator, joints=True)
    taken = table["feasible"].to_numpy(dtype=bool)
    work = workload_table(table, Levers.of(evaluator.body), lift, rows=taken)
    work = pd.concat([work, shift_table(table, evaluator.body, plan, rows=taken)], axis=1)
    share, notes = workforce_share(args.results, named)
    rows = pd.concat([named[["location"]], table, work, share], axis=1)
    body = evaluator.body
    who = (f"{args.manikin} manikin" if args.manikin else "worker") + \
        f": {body.sex}, {body.stature_m:.3f} m, {body.mass_kg:.1f} kg"
    notes = [f"Lift: {lift.lift_frequency:g} a minute, {lift.lift_duration} duration, set down "
             f"at {lift.lift_destination:g} m (revised NIOSH equation, Waters et al. 1993). "
             "Back: static sagittal model, 5 cm erector arm; limits 3,400 N and 6,400 N "
             f"(NIOSH 1981); % capable assumes strength CV 0.277. Note: {LIFTING_INDEX_SCOPE}.",
             f"Shift: {plan.handovers:,} handovers ({plan.rate_per_min:g} a minute, each held "
             f"{plan.hold_s:g} s, over {plan.hours:g} h); capacity, what a joint can still give "
             "(three-compartment fatigue model, Frey-Law et al. 2012); strength: Harbo et al. "
             "2012 at an assumed age of 40, the twin's for the low back; LiFFT: Gallagher et al. "
             "2017.", *notes]
    with tempfile.TemporaryDirectory(prefix=".report-", dir=nearest_existing(output)) as tmp:
        tmp = Path(tmp)
        render_points(table, points, evaluator, tmp / "pictures")
        pages = []
        for i, row in rows.iterrows():
            picture = (tmp / "pictures" / f"point_{i + 1:04d}.png").read_bytes()
            x, y, z = points[i]
            state = "" if row["feasible"] else f" — the twin cannot take it: {row['reason']}"
            pages.append(report_page(
                row, f"Handover at {row['location']}",
                f"box at x={x:+.3f}, y={y:.3f}, z={z:.3f} m (worker frame){state}; {who}",
                picture, notes, flags(row), why=row["workforce_note"]))
        document = "<div style='break-after: page'></div>".join(pages)
        (tmp / "report.html").write_text(document)
        # The numbers as the pages show them, then the rest of the Evaluation as it is.
        text = pd.DataFrame({c: [shown(c, v) for v in rows[c]] for c in PAGE_COLUMNS})
        rest = [c for c in (*EVALUATION_COLUMNS, *work.columns) if c not in PAGE_COLUMNS]
        atomic_write_csv(pd.concat([rows[["location"]], flag_column(rows).rename("flags"), text,
                                    rows[["workforce_note", *rest]]], axis=1),
                         tmp / "report.csv")
        if args.pdf:
            print_pdf(tmp / "report.html", tmp / "report.pdf")
        # All outputs or none: everything made beside the output (one file system), then
        # renamed in, the page last.
        output.mkdir(parents=True, exist_ok=True)
        made = {tmp / "pictures" / f"point_{i + 1:04d}.png": output / f"location_{i + 1:02d}.png"
                for i in range(len(rows))}
        made |= {tmp / name: output / name for name in ("report.csv", "report.pdf", "report.html")
                 if (tmp / name).exists()}
        for source, target in made.items():
            os.replace(source, target)
    print(f"reported {len(rows)} location(s) -> {output}/report.html"
          + (" and report.pdf" if args.pdf else ""), file=sys.stderr)
    return 0
