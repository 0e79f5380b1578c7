"""What the viewer shows, without the browser: the twin re-solved at a box location, the robot
holding the box there, a carry's path played back, and the panel's text.

:class:`HandoverScene` owns a PyBullet :class:`~..scene.world.World` and mirrors it into a viser
scene (:mod:`.mirror`); :meth:`HandoverScene.move` is the one update a box move makes (the
latency benchmark times exactly it).
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd

from ..errors import ConfigError
from ..scene.world import WorkerPosture, World
from ..twin.evaluate import JOINT_PREFIX, Evaluator, evaluate, joint_angles, posture_solver
from ..twin.task import Boundary
from .mirror import SceneMirror

SCORES = {"paper_postural": "paper", "reba": "REBA", "rula": "RULA"}
COMPONENTS = {"paper": ("paper_trunk", "paper_neck", "paper_legs", "paper_left_arm",
                        "paper_right_arm", "paper_hands_above_neck"),
              "REBA": ("reba_trunk", "reba_neck", "reba_legs", "reba_load",
                       "reba_left_upper_arm", "reba_left_lower_arm", "reba_left_wrist",
                       "reba_score_a", "reba_score_b", "reba_score_c"),
              "RULA": ("rula_trunk", "rula_neck", "rula_legs", "rula_left_upper_arm",
                       "rula_left_lower_arm", "rula_left_wrist", "rula_score_d")}
BOX = ["box_x", "box_y", "box_z"]  # a path file's box centre, worker frame [m]
ANGLES = ("trunk_flexion", "trunk_side_bend", "trunk_twist", "neck_flexion",
          "left_upper_arm_flexion", "right_upper_arm_flexion", "left_elbow_flexion",
          "right_elbow_flexion", "left_knee_flexion", "right_knee_flexion")


class Move(NamedTuple):
    """One box move: where, the twin's evaluation there (a row of ``evaluate``) and whether the
    robot holds the box there (``robot`` is ``''`` when it does, else why not)."""

    location: np.ndarray
    row: pd.Series
    robot: str

    @property
    def feasible(self) -> bool:
        return bool(self.row["feasible"])


def check_location(location, boundary: Boundary) -> np.ndarray:
    """A box location the viewer accepts: three finite numbers within ``boundary``."""
    location = np.asarray(location, dtype=float).reshape(-1)
    if location.shape != (3,) or not np.isfinite(location).all():
        raise ConfigError(f"location = {location.tolist()} is not allowed (three finite "
                          "numbers x, y, z [m])")
    for axis, value, low, high in zip("xyz", location, boundary.lower, boundary.upper,
                                      strict=True):
        if not low - 1e-9 <= value <= high + 1e-9:
            raise ConfigError(f"location {axis} = {value:g} is outside the boundary "
                              f"'{boundary.name}' ({low:g} to {high:g} m)")
    return location


def panel_text(move: Move) -> str:
    """The panel's markdown for a move: scores, their components, key angles, the robot."""
    x, y, z = move.location
    lines = [f"**box at ({x:.3f}, {y:.3f}, {z:.3f}) m** (worker frame: x right, y up, "
             "z forward)", ""]
    if not move.feasible:
        return "\n".join([*lines, f"**infeasible**: {move.row['reason']} (not scored)"])
    row = move.row
    lines.append(" · ".join(f"{label} **{int(row[s])}**" for s, label in SCORES.items()))
    for label, items in COMPONENTS.items():
        lines += ["", f"{label}: " + ", ".join(
            f"{c.split('_', 1)[1].replace('_', ' ')} {int(row[c])}" for c in items)]
    lines += ["", "angles [deg]: " + ", ".join(
        f"{a.replace('_', ' ')} {row[a]:.1f}" for a in ANGLES)]
    lines += ["", "robot: " + ("holds the box here" if not move.robot
                                else f"cannot hold it here ({move.robot})")]
    return "\n".join(lines)


class HandoverScene:
    """The twin, the robot and the box, in PyBullet and in a viser server's scene.

    Args:
        evaluator: the worker and the scoring (the study's by default).
        boundary: where the box may be moved.
        server: the viser server to draw into.
        robot: hold the box with the robot at every move (its IK: a few ms more per move).
        gui: also show the scene in PyBullet's own window (needs a display).
    """

    def __init__(self, evaluator: Evaluator, boundary: Boundary, server, robot: bool = True,
                 gui: bool = False):
        self.evaluator, self.boundary, self.with_robot = evaluator, boundary, robot
        self.world = World(evaluator.body, evaluator.task, gui=gui)
        self.names = posture_solver(evaluator).model.joint_names
        self.mirror = SceneMirror(self.world, server)
        self.last: Move | None = None

    def close(self) -> None:
        self.world.close()

    def evaluation(self, location: np.ndarray) -> tuple[pd.Series, WorkerPosture | None]:
        """The twin's evaluation at ``location`` (a row of ``evaluate``, joints included) and
        its solved posture (None where it cannot take the box)."""
        table = evaluate(np.asarray(location, dtype=float)[None], self.evaluator, joints=True)
        row = table.iloc[0]
        return row, (WorkerPosture(self.names, joint_angles(table)[0]) if row["feasible"]
                     else None)

    def solve(self, location) -> Move:
        """The twin at ``location`` (checked against the boundary) and the robot's hold."""
        location = check_location(location, self.boundary)
        row, posture = self.evaluation(location)
        robot = ""
        if posture is not None:
            self.world.pose_worker(posture)
            if self.with_robot:
                reach = self.world.reach(location, posture)
                robot = "" if reach.reachable else reach.reason
            else:
                self.world.bring_robot(location)
        else:
            self.world.pose_worker(None)
            self.world.bring_robot(location)
            robot = "the worker cannot take it here"
        self.world.place_box(location)
        return Move(location, row.drop([c for c in row.index if c.startswith(JOINT_PREFIX)]),
                    robot)

    def move(self, location) -> Move:
        """Move the box: re-solve the twin, pose the robot, update the browser's scene."""
        self.last = self.solve(location)
        self.mirror.update()
        return self.last

    def handover_posture(self, path: pd.DataFrame) -> WorkerPosture | None:
        """The worker's solved posture where a carry's path ends (None where infeasible)."""
        return self.evaluation(path[BOX].to_numpy(float)[-1])[1]

    def show_time(self, path: pd.DataFrame, t: float, posture: WorkerPosture | None) -> None:
        """Pose the scene at time ``t`` [s] of a carry's path table (a baselines path file):
        its last waypoint at or before ``t``; the box and every robot joint by name; the
        worker at rest while the box travels and in ``posture`` at the last waypoint (the
        handover)."""
        k = max(int(np.searchsorted(path["time"].to_numpy(float), t, side="right")) - 1, 0)
        world, row = self.world, path.iloc[k]
        robot = world.robot
        for name, index in robot.body_joints.items():
            if name in path.columns:
                world.p.resetJointState(robot.body, index, float(row[name]),
                                        physicsClientId=world.client)
        world.place_box(row[BOX].to_numpy(float))
        world.pose_worker(posture if k == len(path) - 1 else None)
        self.mirror.update()


def read_path(path: Path) -> pd.DataFrame:
    """A carry's path file, checked for the columns playback needs."""
    try:
        table = pd.read_csv(path)
    except (OSError, ValueError) as error:
        raise ConfigError(f"path file {path}: cannot be read ({error})") from None
    missing = [c for c in ("time", *BOX) if c not in table.columns]
    if missing or table.empty:
        raise ConfigError(f"path file {path} is not a carry's path (missing "
                          f"{missing or 'rows'}; expected results/baselines/paths/*.csv)")
    return table
