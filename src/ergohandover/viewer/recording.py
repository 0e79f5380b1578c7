"""Scene recordings a reviewer opens in a browser without Python: a self-contained HTML page
(viser's client with the recorded scene inside) that plays the baseline comparison of each start
— the twin at the optimised location, then at the shortest-distance one — and the robot's carry
of the box to the optimised location.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ..io.atomic import atomic_write
from ..twin.evaluate import Evaluator
from ..twin.task import Boundary
from .app import free_port, start_server
from .handover import HandoverScene, read_path

HOLD_S = 2.0  # how long each location is shown
CARRY_FPS = 5  # frames per second of a played-back carry (a recording grows with each)


def record_comparison(evaluator: Evaluator, boundary: Boundary, rows: pd.DataFrame,
                      path_file: Path | None) -> str:
    """A standalone HTML recording of one start: the twin at each of ``rows``' locations
    (baselines.csv rows of one start: ``method, x, y, z``) for :data:`HOLD_S` each, then the
    carry of ``path_file`` (a baselines path file), if given."""
    server = start_server("127.0.0.1", free_port())
    scene = HandoverScene(evaluator, boundary, server)
    try:
        recorder = server.get_scene_serializer()
        for _, row in rows.iterrows():
            label = server.scene.add_label("/caption", f"{row['method'].replace('_', ' ')}",
                                           position=(0.0, 0.0, 2.1))
            scene.move(row[["x", "y", "z"]].to_numpy(float))
            recorder.insert_sleep(HOLD_S)
            label.remove()
        if path_file is not None:
            table = read_path(path_file)
            posture = scene.handover_posture(table)
            server.scene.add_label("/caption", "carry to the optimised location",
                                   position=(0.0, 0.0, 2.1))
            for t in np.arange(0.0, table["time"].iloc[-1] + 1e-9, 1 / CARRY_FPS):
                scene.show_time(table, t, posture)
                recorder.insert_sleep(1 / CARRY_FPS)
            recorder.insert_sleep(HOLD_S)
        return recorder.as_html()
    finally:
        server.stop()
        scene.close()


def write_recording(html: str, path: Path) -> Path:
    """Write a recording atomically (a page that is there is whole)."""
    return atomic_write(path, lambda handle: handle.write(html))
