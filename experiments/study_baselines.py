"""Study part `baselines`: the paper's comparison of the optimised location with the naive
shortest-distance location, from its five start points, with the robot's feasibility and
pictures of each.

Usage: python experiments/study_baselines.py [--config ...]

Writes results/baselines/: baselines.csv (one row per start and method), baselines.md,
renders/ (a PNG per start and method, a contact sheet, a GIF of a carry), manifest.json.
"""

from __future__ import annotations

from pathlib import Path

import study_landscape

from ergohandover.cli.baseline import markdown_table, render
from ergohandover.io.atomic import atomic_write, atomic_write_csv
from ergohandover.scene.robot import RobotSpec
from ergohandover.study.baselines import PAPER_STARTS, compare
from ergohandover.study.parts import part_config, run_part, study_main
from ergohandover.twin.evaluate import Evaluator

ROOT = Path(__file__).resolve().parents[1]


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    study_landscape.run(config, results, workers)  # reused when finished
    part = part_config(config, "baselines")

    def work(folder: Path) -> dict:
        landscape = study_landscape.default_landscape(config, workers)
        evaluator, robot = Evaluator(task=study_landscape.study_task(config)), RobotSpec()
        result = compare(PAPER_STARTS, landscape, evaluator, robot)
        atomic_write_csv(result.table, folder / "baselines.csv")
        markdown = markdown_table(result.table)
        atomic_write(folder / "baselines.md", lambda h: h.write(markdown))
        print(markdown, end="")
        if part["render"]:
            render(result, evaluator, robot, folder / "renders")
        return {"starts": len(PAPER_STARTS)}

    run_part("baselines", results / "baselines", part, work, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
