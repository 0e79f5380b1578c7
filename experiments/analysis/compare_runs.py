"""Compare two results folders of the study (e.g. the committed results/ and a rerun made with
``python experiments/run_all.py --force --results /tmp/rerun``) and the landscapes they record.

Compared (both folders are walked; a top-level ``quick/`` is a run of its own, left out): every
CSV in every subfolder, cell for cell: integers, text and empty cells exactly as written; two
cells both written as floating-point numbers (a decimal point or an exponent) within a relative
:data:`FLOAT_RELATIVE` (1e-9: the last digits of a double follow the processor and the order of
a sum; no result is read to 9 significant digits), each column where it was needed printed
with its largest relative difference; the machine-dependent columns and rows of
:data:`TOLERANCES` by their own rule (which replaces the float one), their measured spread
printed; each ``manifest.json``'s ``config`` and ``seeds``. A CSV or manifest in one folder
only differs. Landscapes: the keys the results record (any ``landscape_key`` in a manifest or a
CSV), paired by where they are recorded. Without --cache-a/--cache-b both sides read one cache,
where a key is one file: equal keys are identical by construction (said so). A rerun from an
empty cache has a cache of its own (ERGOHANDOVER_CACHE=DIR); given both caches, each recorded
pair and every other key both caches hold is compared bit for bit (numpy.array_equal of the
arrays' bits), with the number of points and where they differ; a recorded landscape missing
from one differs.

Not compared (each reported as byte-identical or not, never a difference): ``*.md`` (tables.md
and baselines.md render the CSVs compared here with run times, planning seconds and wall-clock-
capped results; README.md is prose); ``*.png``/``*.gif`` renders (their pixels follow the
renderer's and image libraries' versions; the paths they draw, baselines/paths/*.csv, are
compared); the rest of a manifest (command, commit, versions, machine, engine, wall and sweep
times, code hash, cache reuse counts, totals that include wall-clock-capped runs); a landscape
file's metadata but its grid. Exit code: 0 when everything compared matches (within
:data:`FLOAT_RELATIVE` and :data:`TOLERANCES`), 1 when anything differs, 2 on bad usage (one
line naming the argument).
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import math
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd


class Tolerance(NamedTuple):
    files: str  # fnmatch pattern of a CSV's path inside the results folder
    column: str | None  # None: the rule for rows
    kind: str  # time: any value; abs: |a - b| <= limit; rel: relative; rows: left out
    limit: float | None
    reason: str


TOLERANCES = (
    Tolerance("*", "elapsed_s", "time", None, "wall time of a learning run"),
    Tolerance("*", "steps_per_s", "time", None, "speed of a learning run"),
    Tolerance("*", "median_steps_per_s", "time", None, "median speed of a cell's runs"),
    Tolerance("*", "time_s", "time", None, "wall-clock stamp of a trace row"),
    Tolerance("*", "first_reached_s", "time", None, "wall time to the first best score"),
    Tolerance("*", "planning_s", "time", None, "wall time of the robot's planner"),
    Tolerance("baselines/*", "checks", "abs", 9, "the robot planner's pose checks per carry: "
              "OMPL's RRT-Connect is seeded, but floating point differs across processors "
              "(measured: up to +-9 per carry across machines)"),
    Tolerance("baselines/*", "path_length_m", "rel", 1e-12, "a sum of float distances along "
              "the planned path: its last digits follow the processor's floating point"),
    Tolerance("*", None, "rows", None, "runs under a wall-clock cap (budget wall-*, steps "
              "empty or stopped_by time_cap): how far a run gets follows the machine's load"),
)
"""Every exception to exact equality, with its reason."""
FLOAT_RELATIVE = 1e-9
"""Two cells written as floating-point numbers agree when |a - b| <= FLOAT_RELATIVE * max(|a|,
|b|): a double's last digits follow the processor's floating point and the order of a sum (a
rerun's robot clearance differed in the 16th digit), while no table is read to 9 digits."""
FLOAT_CELL = r"[+-]?(?:\d+\.\d*|\.\d+|\d+(?=[eE]))(?:[eE][+-]?\d+)?"
"""A cell written as a floating-point number: a decimal point or an exponent (an integer's
digits alone are compared exactly)."""
LANDSCAPE_FILE = "landscapes/{key}.npz"
"""A landscape's file inside a cache folder (the landscape cache's layout)."""


def tolerance(name: str, column: str | None) -> Tolerance | None:
    """The rule of :data:`TOLERANCES` for ``column`` (None: the row rule) of CSV ``name``."""
    return next((t for t in TOLERANCES if t.column == column
                 and fnmatch.fnmatch(name, t.files)), None)


def wall_capped(table: pd.DataFrame) -> np.ndarray:
    """Rows of a table (read as text) that are runs, or summaries of runs, under a wall clock."""
    empty = pd.Series("", index=table.index)
    return (table.get("budget", empty).str.startswith("wall-") | (table.get("steps", "x") == "")
            | (table.get("stopped_by", empty) == "time_cap")).to_numpy()


def float_cells(cells: np.ndarray) -> np.ndarray:
    """The finite value of each cell written as a floating-point number (:data:`FLOAT_CELL`);
    NaN for an integer, text, an empty cell, inf or nan."""
    text = pd.Series(cells, dtype=object).astype(str)
    values = pd.to_numeric(text.where(text.str.fullmatch(FLOAT_CELL)), errors="coerce")
    values = values.to_numpy(dtype=float)
    return np.where(np.isfinite(values), values, np.nan)


def relative_diff(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """|a - b| relative to the larger magnitude (0 where both are 0)."""
    return np.abs(a - b) / np.maximum(np.maximum(np.abs(a), np.abs(b)), 1e-300)


def spread(rule: Tolerance, a: np.ndarray, b: np.ndarray) -> tuple[bool, str]:
    """Whether the numbers ``a`` and ``b`` agree under ``rule``, and their measured spread."""
    if len(a) == 0:
        return True, "no values"
    diff = np.abs(a - b)
    text = f"max abs diff {diff.max():.3g}"
    if rule.kind == "time":
        floor = 0.0 if rule.column.endswith("_per_s") else 0.05  # times under 50 ms: noise
        big = (a > floor) & (b > floor)
        if big.any():
            ratio = b[big] / a[big]
            text += (f"; B/A over {big.sum()} values{' above 50 ms' if floor else ''}: median "
                     f"{np.median(ratio):.2f}, range {ratio.min():.2f}-{ratio.max():.2f}")
        return True, text
    if rule.kind == "abs":
        return bool(diff.max() <= rule.limit), f"{text} (tolerance {rule.limit:g})"
    relative = relative_diff(a, b).max()
    return bool(relative <= rule.limit), f"max rel diff {relative:.2g} (tolerance {rule.limit:g})"


def compare_tables(name: str, x: pd.DataFrame, y: pd.DataFrame) -> tuple[bool, list[str]]:
    """Compare two CSV tables read as text: whether they agree, and the lines to print (the
    first: identical / within tolerance / DIFFERS; then columns that differ and spreads)."""
    notes, problems = [], []
    if tolerance(name, None):
        cx, cy = wall_capped(x), wall_capped(y)
        if cx.any() or cy.any():
            wx, wy, exact = x[cx], y[cy], [tolerance(name, c) is None for c in x]
            changed = "" if wx.shape != wy.shape or list(wx) != list(wy) else (
                f"; {(wx.to_numpy() != wy.to_numpy())[:, exact].any(axis=1).sum()} of them differ")
            notes.append(f"wall-clock-capped rows left out: A {cx.sum()}, B {cy.sum()}{changed}")
        x, y = x[~cx], y[~cy]
    if list(x.columns) != list(y.columns):
        return False, [f"DIFFERS: columns ({', '.join(sorted(set(x) ^ set(y))) or 'order'})"]
    if len(x) != len(y):
        return False, [f"DIFFERS: {len(x)} rows compared in A, {len(y)} in B", *notes]
    for column in x.columns:
        a, b = x[column].to_numpy(), y[column].to_numpy()
        rule = tolerance(name, column)
        if rule is None:
            rows = np.flatnonzero(a != b)
            if not len(rows):
                continue
            relative = relative_diff(float_cells(a[rows]), float_cells(b[rows]))
            beyond = rows[~(relative <= FLOAT_RELATIVE)]  # NaN (not both floats): beyond
            if len(beyond):
                first = relative[rows == beyond[0]][0]
                problems.append(f"column {column}: {len(beyond)} rows differ, first at line "
                                f"{x.index[beyond[0]] + 2}: {a[beyond[0]]!r} vs "
                                f"{b[beyond[0]]!r}" + ("" if np.isnan(first) else
                                f" (rel diff {first:.2g}, tolerance {FLOAT_RELATIVE:g})"))
            else:
                notes.append(f"{column} (floating point, tolerated): {len(rows)} rows differ "
                             f"in their last digits, max rel diff {relative.max():.2g} "
                             f"(tolerance {FLOAT_RELATIVE:g})")
            continue
        na, nb = pd.to_numeric(a, errors="coerce"), pd.to_numeric(b, errors="coerce")
        both = ~np.isnan(na) & ~np.isnan(nb)
        ok, text = spread(rule, na[both], nb[both])
        if ok and (a[~both] == b[~both]).all():  # empty or text cells must be equal
            notes.append(f"{column} ({rule.kind}, tolerated): {text}")
        else:
            problems.append(f"column {column} beyond its tolerance: {text}")
    head = (f"DIFFERS in {len(problems)} column(s)" if problems else
            "within tolerance" if notes else "identical") + f" ({len(x)} rows compared)"
    return not problems, [head, *problems, *notes]


def walk(root: Path, parts: list[str]) -> dict[str, Path]:
    """Every file under ``root`` by its posix path inside it, but a top-level ``quick/`` (a run
    of its own) and hidden files; only the given parts' folders when ``parts``."""
    found = {}
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root)
        if (path.is_file() and rel.parts[0] != "quick" and not rel.name.startswith(".")
                and (not parts or (len(rel.parts) > 1 and rel.parts[0] in parts))):
            found[rel.as_posix()] = path
    return found


def recorded_keys(value, where: str) -> Iterator[tuple[str, str]]:
    """(where, key) of every ``landscape_key`` in a manifest's JSON ``value``."""
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(
        value, list) else ()
    for k, v in items:
        if k == "landscape_key" and isinstance(v, str):
            yield where, v
        yield from recorded_keys(v, f"{where}:{k}")


def read_landscape(path: Path) -> tuple[dict, dict[str, np.ndarray]]:
    """A landscape file's metadata and arrays (an ``.npz`` with a JSON ``meta`` entry)."""
    with np.load(path, allow_pickle=False) as data:
        return json.loads(str(data["meta"])), {n: data[n] for n in data.files if n != "meta"}


def location(meta: dict, flat: int) -> str:
    """' at (x, y, z) m' of grid point ``flat`` (C order, x slowest), if the grid is known."""
    try:
        box, step = meta["grid"]["boundary"], meta["grid"]["step"]
        shape = [math.floor((box[a][1] - box[a][0]) / step + 1e-9) + 1 for a in "xyz"]
        idx = np.unravel_index(flat, shape)
        return " at (" + ", ".join(f"{box[a][0] + i * step:.3f}"
                                   for a, i in zip("xyz", idx, strict=True)) + ") m"
    except (KeyError, TypeError, ValueError):
        return ""


def compare_landscapes(a: Path, b: Path) -> tuple[bool, str]:
    """Compare two landscape files array by array, bit for bit."""
    missing = [str(p) for p in (a, b) if not p.exists()]
    if missing:
        return False, f"DIFFERS: not in the cache ({', '.join(missing)})"
    (meta, xa), (meta_b, xb) = read_landscape(a), read_landscape(b)
    if meta.get("grid") != meta_b.get("grid") or set(xa) != set(xb):
        return False, "DIFFERS: grids or array names differ"
    points = len(next(iter(xa.values()))) if xa else 0
    problems = []
    for name in sorted(xa):
        u, v = xa[name], xb[name]
        if u.shape != v.shape or u.dtype != v.dtype:
            problems.append(f"{name} ({u.dtype}{u.shape} vs {v.dtype}{v.shape})")
        elif not np.array_equal(bu := u.view(bits := f"u{u.dtype.itemsize}" if u.dtype.kind
                                             in "biuf" else u.dtype), bv := v.view(bits)):
            cells = np.flatnonzero(bu != bv)
            problems.append(f"{name} at {len(cells):,} of {points:,} points, first point "
                            f"{cells[0]}{location(meta, int(cells[0]))}: {u[cells[0]]} vs "
                            f"{v[cells[0]]}")
    if problems:
        return False, "DIFFERS: " + "; ".join(problems)
    return True, f"identical, {len(xa)} arrays of {points:,} points"


def file_kind(name: str) -> str:
    """csv, manifest, render or text (the last two compared for bytes only)."""
    return ("csv" if name.endswith(".csv") else "manifest" if name.endswith("manifest.json")
            else "render" if Path(name).suffix in (".png", ".gif") else "text")


def compare_file(name: str, a: Path, b: Path, keys: tuple[dict, dict]) -> tuple[bool, str]:
    """Compare a file both folders hold: whether it agrees, and the text to print; adds the
    landscape keys it records to ``keys`` (where -> key, for A and for B)."""
    kind = file_kind(name)
    if kind == "csv":
        x, y = (pd.read_csv(p, dtype=str, keep_default_na=False) for p in (a, b))
        for found, table in zip(keys, (x, y), strict=True):
            if "landscape_key" in table:
                found.update((f"{name} line {i + 2}", k)
                             for i, k in enumerate(table["landscape_key"]) if k)
        ok, lines = compare_tables(name, x, y)
        return ok, "\n    ".join(lines)
    if kind == "manifest":
        ma, mb = json.loads(a.read_text()), json.loads(b.read_text())
        keys[0].update(recorded_keys(ma, name))
        keys[1].update(recorded_keys(mb, name))
        diff = [k for k in ("config", "seeds") if ma.get(k) != mb.get(k)]
        return not diff, f"DIFFERS in {diff}" if diff else "config and seeds identical"
    same = "yes" if a.read_bytes() == b.read_bytes() else "no"
    return True, f"not compared ({kind}); byte-identical: {same}"


def compare_keys(pairs: list[tuple[str, str]], caches: tuple[Path, Path] | None) -> bool:
    """Compare the landscapes of each (key in A, key in B), a line each; True when all agree."""
    one_cache = caches is None or caches[0].resolve() == caches[1].resolve()
    same = True
    for ka, kb in pairs:
        if one_cache and ka == kb:
            ok, text = True, "same key in the same cache: identical by construction"
        elif caches is None:
            ok, text = False, "DIFFERS: keys differ; arrays not compared (give --cache-a/-b)"
        else:
            ok, text = compare_landscapes(caches[0] / LANDSCAPE_FILE.format(key=ka),
                                          caches[1] / LANDSCAPE_FILE.format(key=kb))
        print(f"landscape {ka}" + (f" vs {kb}" if kb != ka else "") + f": {text}")
        same &= ok
    return same


def compare(a: Path, b: Path, parts: list[str], caches: tuple[Path, Path] | None) -> bool:
    """Compare results folders ``a`` and ``b``, printing a line per file and landscape; True
    when they agree. ``caches``: their landscape caches (None: one cache for both)."""
    fa, fb = walk(a, parts), walk(b, parts)
    same, keys, csv, csv_bad = True, ({}, {}), 0, 0
    print(f"A = {a}\nB = {b}")
    for name in sorted(set(fa) | set(fb)):
        kind = file_kind(name)
        if name in fa and name in fb:
            ok, text = compare_file(name, fa[name], fb[name], keys)
        else:
            ok = kind not in ("csv", "manifest")
            text = f"{'' if ok else 'DIFFERS: '}missing in {'A' if name not in fa else 'B'}"
        print(f"{name}: {text}")
        same &= ok
        csv += kind == "csv"
        csv_bad += kind == "csv" and not ok
    pairs = sorted({(keys[0][w], keys[1][w]) for w in set(keys[0]) & set(keys[1])})
    if caches and caches[0].resolve() != caches[1].resolve() and not parts:
        held = [{p.stem for p in (c / LANDSCAPE_FILE).parent.glob("*.npz")} for c in caches]
        pairs += [(k, k) for k in sorted(held[0] & held[1]) if (k, k) not in pairs]
    same &= compare_keys(pairs, caches)
    print(f"\n{csv} CSV files compared, {csv_bad} differ; {len(pairs)} landscape key(s) "
          f"compared; {'everything matches' if same else 'DIFFERENCES found'}")
    return same


class Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, exit code 2
        self.exit(2, f"{self.prog}: error: {message}\n")


def main(argv: list[str] | None = None) -> int:
    parser = Parser(prog="compare_runs.py", description=__doc__.split("\n\n")[0] + " Exit code "
                    "0: everything matches (see FLOAT_RELATIVE and TOLERANCES in this "
                    "module); 1: something differs; 2: bad usage.", epilog="tolerated: "
                    f"floating-point cells (rel {FLOAT_RELATIVE:g}, unless a column's own rule "
                    "below); " + "; ".join(
                        f"{t.column or 'wall-clock-capped rows'} ({t.kind}"
                        + ("" if t.limit is None else f" {t.limit:g}") + ")" for t in TOLERANCES))
    parser.add_argument("results_a", metavar="RESULTS_A", type=Path, help="a results folder")
    parser.add_argument("results_b", metavar="RESULTS_B", type=Path, help="the other one")
    parser.add_argument("parts", metavar="PART", nargs="*", default=[], help="compare only "
                        "these parts' folders (e.g. population after a run with --engine ray)")
    parser.add_argument("--cache-a", metavar="DIR", type=Path, help="landscape cache of "
                        "RESULTS_A; with --cache-b, landscapes are compared bit for bit "
                        "(default: one cache for both, where equal keys are identical)")
    parser.add_argument("--cache-b", metavar="DIR", type=Path, help="landscape cache of "
                        "RESULTS_B (e.g. the empty folder a rerun started from)")
    args = parser.parse_args(argv)
    for label, path in (("RESULTS_A", args.results_a), ("RESULTS_B", args.results_b),
                        ("--cache-a", args.cache_a), ("--cache-b", args.cache_b)):
        if path is not None and not path.is_dir():
            parser.error(f"{label} = '{path}' is not a folder")
    if (args.cache_a is None) != (args.cache_b is None):
        parser.error("--cache-a and --cache-b go together (each run's landscape cache)")
    for part in args.parts:
        if not ((args.results_a / part).is_dir() or (args.results_b / part).is_dir()):
            parser.error(f"PART = '{part}' is not a folder of RESULTS_A or RESULTS_B")
    caches = None if args.cache_a is None else (args.cache_a, args.cache_b)
    return 0 if compare(args.results_a, args.results_b, args.parts, caches) else 1


if __name__ == "__main__":
    sys.exit(main())
