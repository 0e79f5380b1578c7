"""The baselines' files beside their table: a path CSV per planned carry, and pictures (a PNG per
start and location, a contact sheet, a GIF per planned carry). The ``baseline`` command and the
study's baselines part both write them from a :class:`~.comparison.Comparison`."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from ...io.atomic import atomic_write_csv
from ...scene.robot import RobotSpec
from ...twin.evaluate import Evaluator


def write_paths(result, evaluator: Evaluator, robot: RobotSpec, folder: Path) -> list[Path]:
    """A path CSV per planned carry (``start<i>_<method>.csv``, see
    :func:`~...scene.carries.path_table`)."""
    from ...scene.carries import path_table
    from ...scene.world import World

    folder.mkdir(parents=True, exist_ok=True)
    written = []
    with World(evaluator.body, evaluator.task, robot) as world:
        for i, (row, plan) in enumerate(zip(result.table.to_dict("records"), result.plans,
                                            strict=True)):
            if plan.ok:
                name = f"start{i // 2 + 1}_{row['method']}.csv"
                written.append(atomic_write_csv(path_table(world, plan), folder / name))
    print(f"wrote {len(written)} path files into {folder}", file=sys.stderr)
    return written


def render(result, evaluator: Evaluator, robot: RobotSpec, folder: Path,
           workers: int = 1) -> list[Path]:
    """A PNG per row (the robot at the handover: the carry's last pose, else the best hold it
    finds there), a contact sheet of them and a GIF per planned carry; the rows are rendered
    over ``workers`` processes, each in a scene of its own (every picture sets the whole
    scene, so where it is drawn does not change it)."""
    from ...executor import LocalExecutor
    from ...scene.scene_render import contact_sheet, short_label

    folder.mkdir(parents=True, exist_ok=True)
    rows = result.table.to_dict("records")
    jobs = [(evaluator, robot, row, plan, posture, folder / f"start{i // 2 + 1}_{row['method']}")
            for i, (row, plan, posture) in enumerate(zip(rows, result.plans, result.postures,
                                                         strict=True))]
    with LocalExecutor(workers) as executor:
        drawn = list(executor.map(_render_row, jobs))
    cells = [(views, short_label(row, i // 2 + 1))
             for i, (row, (views, _)) in enumerate(zip(rows, drawn, strict=True))]
    sheet = contact_sheet(cells, folder / "baseline_sheet.png")
    paths = [path for _, written in drawn for path in written[:1]]
    gifs = [path for _, written in drawn for path in written[1:]]
    print(f"wrote {len(paths)} pictures, {sheet.name} and {len(gifs)} GIFs into {folder}",
          file=sys.stderr)
    return [*paths, sheet, *gifs]


def _render_row(job: tuple):
    """One row's picture (and its carry's GIF, when planned), in a scene of its own: the
    views drawn and the files written."""
    from ...scene.render import save_png
    from ...scene.scene_render import SceneRenderer, baseline_caption, carry_gif
    from ...scene.world import World

    evaluator, robot, row, plan, posture, stem = job
    with SceneRenderer(World(evaluator.body, evaluator.task, robot)) as renderer:
        location = np.array([row["x"], row["y"], row["z"]])
        if plan.ok:
            last = plan.waypoints[-1]
            arms, lift = last.q, last.lift
        else:  # the hold found at the location on its own, else the lowest lift's try
            reach, lift = renderer.world.hold_at_some_lift(location, posture)
            arms = reach.q
        renderer.pose(location, arms, posture, lift)
        views = renderer.views()
        written = [save_png(views, baseline_caption(row), stem.with_suffix(".png"))]
        if plan.ok:
            written.append(carry_gif(renderer, plan, posture, stem.with_suffix(".gif")))
    return views, written


def start_numbers(table):
    """Each row's start, numbered from 1 in the table's order (the paper's)."""
    return table.groupby(["start_x", "start_y", "start_z"], sort=False).ngroup() + 1


def record_start(table, start: int, boundary, evaluator: Evaluator, paths: Path) -> str | None:
    """One start's scene recording (a page that opens in a browser without Python): the twin
    at each of its locations, then the robot's carry to the optimised one from ``paths`` (when
    planned); None when the table has no such start. Needs the viewer extra."""
    from ...viewer.recording import record_comparison

    rows = table[start_numbers(table) == start]
    if rows.empty:
        return None
    carry = paths / f"start{start}_optimised.csv"
    return record_comparison(evaluator, boundary, rows, carry if carry.exists() else None)


def record(table, boundary, evaluator: Evaluator, paths: Path, folder: Path) -> list[Path]:
    """:func:`record_start` for every start, into ``start<k>.html``; nothing, said in one line,
    without the viewer extra."""
    import importlib.util

    if importlib.util.find_spec("viser") is None:
        print("recordings skipped: the viewer extra is not installed (pip install -e "
              "'.[viewer]')", file=sys.stderr)
        return []
    from ...viewer.recording import write_recording

    folder.mkdir(parents=True, exist_ok=True)
    written = [write_recording(record_start(table, start, boundary, evaluator, paths),
                               folder / f"start{start}.html")
               for start in sorted(start_numbers(table).unique())]
    print(f"wrote {len(written)} recordings into {folder}", file=sys.stderr)
    return written
