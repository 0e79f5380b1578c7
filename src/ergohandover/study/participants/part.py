"""Study part `participants`: the paper's five-person VR experiment, in simulation.

Each simulated worker (5th-percentile woman to 95th-percentile man) is scored at the location
optimised for the default worker (what the paper deploys to everyone), at the location optimised
for itself, and at the shortest-distance locations from the VR study's two start points.

Writes results/participants/: participants.csv (with whether the default robot can hold the
box at each worker's optimised locations), manifest.json. The default worker's landscape
is the `landscape` part's; the others are swept side by side on the engine at the configured
(coarser) step. All come from the landscape cache.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ...io.atomic import atomic_write_csv
from ...scene.robot import RobotSpec
from ..baselines.reachability import holds
from ..config import StudyConfig
from ..engines import Engine
from ..resume import run_part
from ..shared import default_landscape, grid_of, landscapes
from .simulated import DEFAULT_WORKER, participant_study

SERVED = ("default-optimised", "own-optimised")  # the locations the robot hands over at


def with_robot(table: pd.DataFrame, evaluators: dict, workers: int) -> pd.DataFrame:
    """Can the default robot hold the box at each worker's optimised locations, with that
    worker gripping it there? Adds ``robot_held`` (0/1, empty for the other rows),
    ``robot_reason`` and ``robot_clearance_m``."""
    table = table.copy()
    table["robot_held"] = pd.Series([pd.NA] * len(table), dtype="Int64")
    table["robot_reason"] = pd.Series([pd.NA] * len(table), dtype=object)
    table["robot_clearance_m"] = float("nan")
    for worker, rows in table[table["location"].isin(SERVED)].groupby("worker", sort=False):
        held = holds(rows[["x", "y", "z"]].to_numpy(), evaluators[worker], RobotSpec(), workers)
        table.loc[rows.index, "robot_held"] = held["held"].to_numpy()
        table.loc[rows.index, "robot_reason"] = held["reason"].to_numpy()
        table.loc[rows.index, "robot_clearance_m"] = held["clearance_m"].to_numpy()
    return table


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.participants

    def work(folder: Path) -> dict:
        evaluators = {name: config.evaluator(name)
                      for name in dict.fromkeys([DEFAULT_WORKER, *part.workers])}
        found = {DEFAULT_WORKER: default_landscape(config, engine)}
        # The other workers' landscapes, swept side by side wherever they share a grid (the
        # paper-code boundary is the same for everyone; the body boundary is each worker's).
        grids: dict = {}
        for name in evaluators:
            if name != DEFAULT_WORKER:
                grid = grid_of(evaluators[name], config.landscape.boundary, part.step)
                grids.setdefault(grid, []).append(name)
        for grid, names in grids.items():
            found.update(zip(names, landscapes(engine, [evaluators[n] for n in names], grid),
                             strict=True))
        found = {name: found[name] for name in evaluators}
        table = participant_study(found, evaluators)
        table = with_robot(table, evaluators, engine.workers)
        atomic_write_csv(table, folder / "participants.csv")
        return {"workers": list(found)}

    return run_part("participants", results / "participants",
                    config.part_inputs("participants"), work, force=force, engine=engine)
