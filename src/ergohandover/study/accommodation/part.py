"""Study part `accommodation`: where does a handover suit most of a workforce?

A workforce of 1,000 (the configuration's size) is drawn from the body model fitted to the ANSUR
II survey. Each worker's twin takes the box at every point of a coarse grid on the default
worker's boundary, and at every headline location; there its posture is scored error-free and
measured as a site would (the measured error model), and the location suits the worker when
REBA and RULA are both within their limits (:mod:`ergohandover.study.accommodation.zone`). The
workers run as independent jobs on the study's engine (the local pool or Ray); a worker's cost
is mostly the twin's warm-start lattice, solved once per body, so a finer grid costs little
more and more workers cost in proportion.

Over a working day: each worker's shoulder, elbow and low-back moments at each posture, as
shares of that worker's strength (:mod:`ergohandover.workload.strength`), through a shift of
handovers at each rate and hold of the shift section (the three-compartment fatigue model,
:mod:`ergohandover.workload.fatigue`), give the share of the workforce that ends the shift with
enough of every joint's capacity left.

Writes results/accommodation/:
  cells.csv      every grid point: the share of the workforce that can take the box there, and
                 the share served (REBA and RULA within limits) error-free and as measured, each
                 with its 95 % bootstrap interval over workers
  locations.csv  the same at each headline location
  zone.csv       per kind (exact, measured): the cells whose share reaches the stated share, those
                 whose interval's lower end does, and the largest box of cells all in the zone
  workers.csv    each worker's body and, at the recommended location (the nominal optimum),
                 feasibility, REBA, RULA, suited or not, and the chance as measured
  shift.csv      per handover rate and hold of the shift section (its 8-hour shift), at each
                 headline location: the share of the workforce that ends the shift with at
                 least the section's ``keep`` of every joint's capacity (interval over
                 workers), and the share with a joint that fails during it
  shift_zone.csv per rate and hold: the grid's cells where that share reaches the stated share,
                 and the cell of the largest share
  manifest.json
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...io.atomic import atomic_write_csv
from ...landscape.grid import Grid
from ...twin.evaluate import Evaluator
from ...workload.strength import JOINTS, shift_outcome
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..robustness.recorded import headline_locations
from ..shared import grid_of, run_jobs
from ..shift.config import ShiftConfig
from ..workforce import Workforce, bodies, sample_workforce
from .config import AccommodationConfig
from .zone import accommodated, largest_box, shares

RECOMMENDED = "nominal optimum"
"""The headline location the README's row reads."""
KINDS = ("exact", "measured")


def share_columns(exact: np.ndarray, chance: np.ndarray, feasible: np.ndarray,
                  part: AccommodationConfig) -> pd.DataFrame:
    """Per location (the columns of the workers x locations arrays): who can take the box, and
    the shares served error-free and as measured with their intervals."""
    out = {"feasible_share": feasible.mean(axis=0)}
    rng = np.random.default_rng(part.bootstrap_seed)
    for kind, values in (("exact", exact.astype(np.float32)), ("measured", chance)):
        share, low, high = shares(values, rng, part.bootstrap)
        out |= {f"{kind}_share": share, f"{kind}_low": low, f"{kind}_high": high}
    return pd.DataFrame(out).round(4)


def zone_rows(cells: pd.DataFrame, grid: Grid, part: AccommodationConfig,
              recommended: np.ndarray) -> list[dict]:
    """Per kind: the zone (share at least ``part.share``), its sure part (interval's lower end
    at least that) and its largest box of cells."""
    rows = []
    for kind in KINDS:
        inside = cells[f"{kind}_share"].to_numpy() >= part.share
        box = largest_box(inside.reshape(grid.shape))
        row = {"kind": kind, "share": part.share, "cells": int(inside.sum()),
               "cells_sure": int((cells[f"{kind}_low"].to_numpy() >= part.share).sum()),
               "volume_l": round(float(inside.sum()) * grid.step**3 * 1000, 1),
               "best_share": float(cells[f"{kind}_share"].max()),
               "recommended_in_zone": bool(inside[grid.nearest_cell(recommended)])}
        if box is not None:
            lo = grid.boundary.lower + np.array([s.start for s in box]) * grid.step
            hi = grid.boundary.lower + np.array([s.stop - 1 for s in box]) * grid.step
            row |= {"box_cells": int(np.prod([s.stop - s.start for s in box])),
                    **{f"box_{a}_min": round(float(v), 4) for a, v in zip("xyz", lo, strict=True)},
                    **{f"box_{a}_max": round(float(v), 4) for a, v in zip("xyz", hi, strict=True)}}
        rows.append(row)
    return rows


def workforce_shifts(stacked: dict[str, np.ndarray], shift: ShiftConfig, grid: Grid,
                     named: pd.DataFrame, part: AccommodationConfig
                     ) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The workforce over a shift of each of the shift section's plans: at each headline
    location, the share whose every joint ends it with at least ``shift.keep`` of its
    capacity (its 95 % bootstrap interval over workers) and the share with a joint that fails;
    over the grid, the cells where that share reaches ``part.share``, those whose interval's
    lower end does, and the cell of the largest share."""
    shares_of = {joint: stacked[f"{joint}_share"] for joint in JOINTS}
    rng = np.random.default_rng([part.bootstrap_seed, 1])  # the shifts' own resamples
    rows, zones = [], []
    for plan in shift.plans():
        found = shift_outcome(shares_of, plan, shift.keep)
        share, low, high = shares(found["kept"], rng, part.bootstrap)
        fails = found["fails"].mean(axis=0)
        said = {"rate_per_min": plan.rate_per_min, "hold_s": plan.hold_s, "hours": plan.hours,
                "keep": shift.keep}
        for i, row in named.iterrows():
            j = grid.size + i
            rows.append({**said, "location": row["location"], "x": row["x"], "y": row["y"],
                         "z": row["z"], "workers": len(found["kept"]),
                         "kept_share": share[j], "kept_low": low[j], "kept_high": high[j],
                         "fails_share": fails[j]})
        best = int(np.argmax(share[:grid.size]))
        zones.append({**said, "share": part.share,
                      "cells": int((share[:grid.size] >= part.share).sum()),
                      "cells_sure": int((low[:grid.size] >= part.share).sum()),
                      "best_share": share[best],
                      **dict(zip(("best_x", "best_y", "best_z"), grid.point(best), strict=True))})
    return pd.DataFrame(rows).round(4), pd.DataFrame(zones).round(4)


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.accommodation

    def work(folder: Path) -> dict:
        table = sample_workforce(Workforce(part.size, part.seed, part.female_share))
        evaluators = [Evaluator(body, config.task()) for body in bodies(table)]
        grid = grid_of(config.evaluator(), part.boundary, part.step)
        named = headline_locations(results)
        points = np.vstack([grid.points(), named[["x", "y", "z"]].to_numpy(float)])
        print(f"  {len(table)} workers on {grid.describe()} and {len(named)} headline "
              f"locations ({engine.name} engine)")
        seeds = np.random.SeedSequence(part.error_seed).spawn(len(evaluators))
        jobs = [(e, points, part.reba_max, part.rula_max, part.draws, s)
                for e, s in zip(evaluators, seeds, strict=True)]
        found = run_jobs(engine, accommodated, jobs, "workers")
        stacked = {k: np.stack([f[k] for f in found]) for k in found[0]}
        columns = share_columns(stacked["exact"], stacked["chance"], stacked["feasible"], part)
        cells = pd.concat([pd.DataFrame(grid.points().round(4), columns=list("xyz")),
                           columns.iloc[:grid.size].reset_index(drop=True)], axis=1)
        at = pd.concat([named, columns.iloc[grid.size:].reset_index(drop=True)], axis=1)
        at.insert(1, "workers", len(table))
        recommended = named.index[named["location"] == RECOMMENDED][0] + grid.size
        workers = table[["worker", "sex", "stature_m", "mass_kg"]].copy()
        for key in ("feasible", "reba", "rula", "exact", "chance"):
            workers[key] = stacked[key][:, recommended]
        workers["suited_cells"] = stacked["exact"][:, :grid.size].sum(axis=1)
        zone = pd.DataFrame(zone_rows(cells, grid, part,
                                      named.loc[named["location"] == RECOMMENDED,
                                                ["x", "y", "z"]].to_numpy(float)[0]))
        over_shift, shift_zone = workforce_shifts(stacked, config.shift, grid, named, part)
        for name, frame in (("cells", cells), ("locations", at), ("zone", zone),
                            ("workers", workers), ("shift", over_shift),
                            ("shift_zone", shift_zone)):
            atomic_write_csv(frame, folder / f"{name}.csv")
        return {"grid": grid.describe(), "workers": len(table)}

    return run_part("accommodation", results / "accommodation",
                    config.part_inputs("accommodation"), work,
                    seeds={"workforce": part.seed, "error": part.error_seed,
                           "bootstrap": part.bootstrap_seed}, force=force, engine=engine)
