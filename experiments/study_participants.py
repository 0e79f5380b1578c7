"""Study part `participants`: the paper's five-person VR experiment, in simulation.

Each simulated worker (5th-percentile woman to 95th-percentile man) is scored at the location
optimised for the default worker (what the paper deploys to everyone), at the location optimised
for itself, and at the shortest-distance locations from the VR study's two start points.

Usage: python experiments/study_participants.py [--config ...]

Writes results/participants/: participants.csv, manifest.json. The default worker's landscape
is the `landscape` part's; the others are swept at the configured (coarser) step. All come from
the landscape cache.
"""

from __future__ import annotations

from pathlib import Path

import study_landscape
from study_landscape import landscape_for

from ergohandover.io.atomic import atomic_write_csv
from ergohandover.study.participants import DEFAULT_WORKER, participant_study
from ergohandover.study.parts import part_config, run_part, study_main
from ergohandover.twin.anthropometry import BodySpec

ROOT = Path(__file__).resolve().parents[1]


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
        atomic_write_csv(table, folder / "participants.csv")
        return {"workers": list(landscapes)}

    run_part("participants", results / "participants", part, work, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
