"""Study part `baselines`: the paper's comparison of the optimised location with the naive
shortest-distance location, from its five start points, with the robot's feasibility and
pictures of each. As in the paper, the optimised location is where the learner ended: the best
location the configured agent found on the configured target and budget of the `learning` part
(``baselines.location``); the landscape's argmin is recorded beside it.

Writes results/baselines/: baselines.csv (one row per start and method, with the robot's
planned carry), baselines.md (with each path file replayed on urdf/robot_default.urdf: deepest
self-penetration, largest joint step), paths/ (a CSV per planned carry: time, box pose, every
robot joint), other_starts.csv (carries to the optimum from starts drawn around the worker),
reachability.csv and reachability_summary.csv (where the robot can hold the box over the
configured boundaries, and the best location of the landscape it can hold), renders/ (a PNG
per start and method, a contact sheet, a GIF per planned carry), recordings/ (a scene
recording per start that opens in a browser without Python; with the viewer extra),
manifest.json.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
from tqdm import tqdm

from ...io.atomic import atomic_write, atomic_write_csv
from ...landscape.grid import parse_boundary
from ...scene.carries import replay
from ...scene.robot import RobotSpec
from ...scene.robot_urdf import cached_robot_urdf
from ..config import StudyConfig
from ..engines import Engine
from ..learning.recorded import learned_location
from ..resume import run_part
from ..shared import default_landscape
from .comparison import PAPER_STARTS, compare, markdown_table, reasonable_starts
from .outputs import record, render, write_paths
from .reachability import reachability, restricted_optimum

CHECKOUT_URDF = Path(__file__).resolve().parents[4] / "urdf" / "robot_default.urdf"
"""The committed robot URDF of the checkout: the file a user loads the path files on."""


def robot_urdf_file() -> Path:
    """The committed robot URDF; outside a checkout, the same robot written from the default
    RobotSpec (tests/test_robot_urdf.py keeps the two equal)."""
    return CHECKOUT_URDF if CHECKOUT_URDF.exists() else cached_robot_urdf(RobotSpec())


def reach_summary(reach: pd.DataFrame, best, steps: dict) -> pd.DataFrame:
    """One row per boundary: the share of its grid the robot holds; and both optima of the
    landscape (the same in every row)."""
    rows = []
    for name, grid in reach.groupby("boundary", sort=False):
        rows.append({
            "boundary": name, "step_m": steps[name], "locations": len(grid),
            "held": int(grid["held"].sum()), "held_fraction": float(grid["held"].mean()),
            "held_fraction_twin_feasible": float(grid.loc[grid["twin_feasible"] == 1,
                                                          "held"].mean()),
            "smallest_clearance_m": float(grid["clearance_m"].min()),
            "score": best.score, "optimum": best.best,
            "optimum_x": best.best_location[0], "optimum_y": best.best_location[1],
            "optimum_z": best.best_location[2], "held_optimum": best.held,
            "held_x": best.held_location[0], "held_y": best.held_location[1],
            "held_z": best.held_location[2], "held_rank": best.rank})
    return pd.DataFrame(rows)


def replayed(table: pd.DataFrame, paths: list[Path]) -> pd.DataFrame:
    """Each path file played back on the committed robot URDF in a client of its own: the
    deepest self-penetration [mm] and the largest joint step [rad] of every planned carry."""
    urdf = robot_urdf_file()
    # Each replay loads the URDF and steps every pose (a few seconds a path): a bar says so.
    played = {path.stem: replay(pd.read_csv(path), urdf)
              for path in tqdm(paths, desc="replaying carries on the URDF", unit="path")}
    names = [f"start{i // 2 + 1}_{m}" for i, m in enumerate(table["method"])]
    table = table.copy()
    table["replay_penetration_mm"] = [
        1000 * played[n].self_penetration_m if n in played else np.nan for n in names]
    table["replay_joint_step_rad"] = [
        played[n].revolute_step_rad if n in played else np.nan for n in names]
    return table


def run(config: StudyConfig, results: Path, engine: Engine, force: bool = False) -> bool:
    part = config.baselines

    def work(folder: Path) -> dict:
        landscape = default_landscape(config, engine)
        evaluator, robot = config.evaluator(), RobotSpec()
        learned = learned_location(results, part.location)
        location = learned[["x", "y", "z"]].to_numpy(dtype=float)
        result = compare(PAPER_STARTS, landscape, evaluator, robot, seed=part.seed,
                         location=location, executor=engine.executor(isolated=True))
        table = result.table
        source = (f"{learned['agent']} {learned['target']} {learned['budget']} run "
                  f"{int(learned['run'])}")
        table["location_source"] = np.where(table["method"] == "optimised", source, "")
        for axis in "xyz":
            table[f"argmin_{axis}"] = learned[f"argmin_{axis}"]
        table = replayed(table, write_paths(result, evaluator, robot, folder / "paths"))
        atomic_write_csv(table, folder / "baselines.csv")
        markdown = markdown_table(table)
        atomic_write(folder / "baselines.md", lambda h: h.write(markdown))
        print(markdown, end="")
        starts = reasonable_starts(np.random.default_rng(part.starts_seed), part.other_starts)
        others = compare(starts, landscape, evaluator, robot, seed=part.seed,
                         methods=("optimised",), location=location,
                         executor=engine.executor(isolated=True)).table
        atomic_write_csv(others, folder / "other_starts.csv")
        reach = pd.concat([reachability(
            parse_boundary(name, evaluator.body, evaluator.task), evaluator, robot, step,
            engine.workers).assign(boundary=name) for name, step in part.reach.items()])
        atomic_write_csv(reach, folder / "reachability.csv")
        best = restricted_optimum(landscape, evaluator, robot, workers=engine.workers)
        atomic_write_csv(reach_summary(reach, best, part.reach),
                         folder / "reachability_summary.csv")
        if part.render:
            render(result, evaluator, robot, folder / "renders", engine.workers)
            record(table, landscape.grid.boundary, evaluator, folder / "paths",
                   folder / "recordings")
        return {"starts": len(PAPER_STARTS),
                "carries_planned": sum(plan.ok for plan in result.plans),
                "other_starts_planned": int(others["robot_feasible"].sum()),
                "held_fraction": {name: float(grid["held"].mean())
                                  for name, grid in reach.groupby("boundary", sort=False)}}

    return run_part("baselines", results / "baselines", config.part_inputs("baselines"), work,
                    seeds={"planner": part.seed}, force=force, engine=engine)
