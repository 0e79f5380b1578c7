"""Study part `participants`: the paper's five-person VR experiment, in simulation.

Each simulated worker (5th-percentile woman to 95th-percentile man) is scored at the location
optimised for the default worker (what the paper deploys to everyone), at the location optimised
for itself, and at the shortest-distance locations from the VR study's two start points.

Usage: python experiments/study_participants.py [--config ...]

Writes results/participants/: participants.csv (with whether the default robot can hold the
box at each worker's optimised locations), manifest.json. The default worker's landscape
is the `landscape` part's; the others are swept at the configured (coarser) step. All come from
the landscape cache.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import study_landscape
from study_landscape import landscape_for

from ergohandover.io.atomic import atomic_write_csv
from ergohandover.scene.robot import RobotSpec
from ergohandover.study.participants import DEFAULT_WORKER, participant_study
from ergohandover.study.parts import part_config, run_part, study_main
from ergohandover.study.reachability import holds
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator

ROOT = Path(__file__).resolve().parents[1]
SERVED = ("default-optimised", "own-optimised")  # the locations the robot hands over at


def with_robot(table: pd.DataFrame, task, workers: int) -> pd.DataFrame:
    """Can the default robot hold the box at each worker's optimised locations, with that
    worker gripping it there? Adds ``robot_held`` (0/1, empty for the other rows),
    ``robot_reason`` and ``robot_clearance_m``."""
    table = table.copy()
    table["robot_held"] = pd.Series([pd.NA] * len(table), dtype="Int64")
    table["robot_reason"] = pd.Series([pd.NA] * len(table), dtype=object)
    table["robot_clearance_m"] = float("nan")
    for worker, rows in table[table["location"].isin(SERVED)].groupby("worker", sort=False):
        evaluator = Evaluator(BodySpec.from_percentile(worker), task)
        held = holds(rows[["x", "y", "z"]].to_numpy(), evaluator, RobotSpec(), workers)
        table.loc[rows.index, "robot_held"] = held["held"].to_numpy()
        table.loc[rows.index, "robot_reason"] = held["reason"].to_numpy()
        table.loc[rows.index, "robot_clearance_m"] = held["clearance_m"].to_numpy()
    return table


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    study_landscape.run(config, results, workers)  # reused when finished
    part = part_config(config, "participants")

    def work(folder: Path) -> dict:
        landscapes = {DEFAULT_WORKER: study_landscape.default_landscape(config, workers)}
        task = study_landscape.study_task(config)
        own = {"boundary": config["landscape"]["boundary"], "step": part["step"]}
        for name in part["workers"]:
            if name != DEFAULT_WORKER:
                landscapes[name] = landscape_for(BodySpec.from_percentile(name), own, workers,
                                                 task=task)
        table = participant_study(landscapes, task)
        table = with_robot(table, task, workers)
        atomic_write_csv(table, folder / "participants.csv")
        return {"workers": list(landscapes)}

    run_part("participants", results / "participants", part, work, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
