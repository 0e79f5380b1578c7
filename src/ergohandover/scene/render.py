"""Pictures of the twin holding the box: PyBullet's TinyRenderer (headless), two views side by
side (three-quarter front and side) with the location and its scores written underneath."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from ..frames import worker_to_world
from ..io.atomic import atomic_write
from ..sim import connect_direct
from ..sim import pybullet as _pybullet
from ..twin.anthropometry import BodySpec
from ..twin.task import TaskSpec
from ..twin.urdf import load_worker

VIEW_SIZE = 480
CARDBOARD = (0.72, 0.55, 0.33, 1.0)
HANDLE = (0.15, 0.15, 0.15, 1.0)
FLOOR = (0.85, 0.85, 0.82, 1.0)
# Camera eye positions, world frame (worker at the origin facing +x, left = +y).
VIEWS = {"three-quarter": (2.7, 1.6, 1.7), "side": (0.3, 3.4, 1.1)}


class Renderer:
    """A DIRECT-mode PyBullet world with the worker, a floor and a box; one per process."""

    def __init__(self, body: BodySpec, task: TaskSpec):
        p = self.p = _pybullet()
        self.body, self.task = body, task
        self.client = connect_direct()
        self.worker = load_worker(self.client, body)
        floor = p.createVisualShape(p.GEOM_BOX, halfExtents=[1.5, 1.5, 0.005], rgbaColor=FLOOR,
                                    physicsClientId=self.client)
        p.createMultiBody(0, baseVisualShapeIndex=floor, basePosition=[0.3, 0, -0.005],
                          physicsClientId=self.client)
        half = [task.box_depth / 2, task.box_width / 2, task.box_height / 2]  # world x, y, z
        box = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=CARDBOARD,
                                  physicsClientId=self.client)
        grip = p.createVisualShape(p.GEOM_CAPSULE, radius=0.012, length=0.10, rgbaColor=HANDLE,
                                   physicsClientId=self.client)
        self.box = p.createMultiBody(0, baseVisualShapeIndex=box, physicsClientId=self.client)
        # Handles run front to back (world x) on the box's side faces.
        along_x = p.getQuaternionFromEuler([0, np.pi / 2, 0])
        self.handles = [p.createMultiBody(0, baseVisualShapeIndex=grip,
                                          baseOrientation=along_x, physicsClientId=self.client)
                        for _ in range(2)]
        self.along_x = along_x

    def close(self) -> None:
        self.p.disconnect(self.client)

    def pose(self, joint_names, q: np.ndarray, location: np.ndarray) -> None:
        """Set the worker's joints (by name) and place the box at ``location`` (worker frame)."""
        p = self.p
        for name, angle in zip(joint_names, q, strict=True):
            p.resetJointState(self.worker.body_id, self.worker.joints[name], float(angle),
                              physicsClientId=self.client)
        centre = worker_to_world(location)
        p.resetBasePositionAndOrientation(self.box, centre.tolist(), [0, 0, 0, 1],
                                          physicsClientId=self.client)
        for handle, grip in zip(self.handles, self.task.handles(location[None]), strict=True):
            p.resetBasePositionAndOrientation(handle, worker_to_world(grip[0]).tolist(),
                                              self.along_x, physicsClientId=self.client)

    def views(self) -> Image.Image:
        """The current scene from each camera, side by side."""
        p = self.p
        target = [0.25, 0.0, 1.0]
        projection = p.computeProjectionMatrixFOV(42, 1.0, 0.1, 10.0)
        images = []
        for eye in VIEWS.values():
            view = p.computeViewMatrix(eye, target, [0, 0, 1])
            _, _, rgba, _, _ = p.getCameraImage(
                VIEW_SIZE, VIEW_SIZE, view, projection, renderer=p.ER_TINY_RENDERER,
                lightDirection=[2, 1, 3], shadow=1, physicsClientId=self.client)
            rgb = np.asarray(rgba, dtype=np.uint8).reshape(VIEW_SIZE, VIEW_SIZE, 4)[:, :, :3]
            images.append(Image.fromarray(rgb))
        canvas = Image.new("RGB", (VIEW_SIZE * len(images), VIEW_SIZE), "white")
        for i, image in enumerate(images):
            canvas.paste(image, (i * VIEW_SIZE, 0))
        return canvas


def caption_lines(row) -> list[str]:
    """What is written under a picture: the location, feasibility, scores and key angles."""
    head = f"box at x={row['x']:+.3f} y={row['y']:.3f} z={row['z']:.3f} m (worker frame)"
    if not row["feasible"]:
        return [head, f"INFEASIBLE: {row['reason']}"]
    return [
        head,
        f"REBA {row['reba']} (A {row['reba_score_a']}, B {row['reba_score_b']}, action level "
        f"{row['reba_action_level']})   RULA {row['rula']}   paper postural "
        f"{row['paper_postural']}",
        f"trunk {row['trunk_flexion']:.0f} deg  neck {row['neck_flexion']:.0f}  knees "
        f"{row['left_knee_flexion']:.0f}  upper arms {row['left_upper_arm_flexion']:.0f}/"
        f"{row['right_upper_arm_flexion']:.0f}  elbows {row['left_elbow_flexion']:.0f}/"
        f"{row['right_elbow_flexion']:.0f}",
    ]


def save_png(image: Image.Image, lines: list[str], path: str | os.PathLike) -> Path:
    """Write ``image`` with ``lines`` of text underneath, atomically."""
    font = ImageFont.load_default()
    band = 8 + 18 * len(lines)
    out = Image.new("RGB", (image.width, image.height + band), "white")
    out.paste(image, (0, 0))
    draw = ImageDraw.Draw(out)
    for i, line in enumerate(lines):
        draw.text((10, image.height + 6 + 18 * i), line, fill="black", font=font)
    return atomic_write(path, lambda handle: out.save(handle, format="PNG"), binary=True)


def render_points(table, points: np.ndarray, evaluator, folder: Path) -> None:
    """One PNG per point: the twin in the posture of its row (``table`` has the joint columns
    of ``evaluate(..., joints=True)``)."""
    from tqdm import tqdm

    from ..twin.evaluate import joint_angles, posture_solver

    folder.mkdir(parents=True, exist_ok=True)
    names = posture_solver(evaluator).model.joint_names
    q = joint_angles(table)
    renderer = Renderer(evaluator.body, evaluator.task)
    try:
        for i in tqdm(range(len(points)), desc="render", unit="png", file=sys.stderr,
                      disable=len(points) < 5):
            renderer.pose(names, q[i], points[i])
            save_png(renderer.views(), caption_lines(table.iloc[i]),
                     folder / f"point_{i + 1:04d}.png")
    finally:
        renderer.close()
