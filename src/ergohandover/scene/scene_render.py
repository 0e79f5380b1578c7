"""Pictures of the handover scene (worker, robot, box): one PNG per start point and location
with its scores written underneath (the paper's "posture scores by heuristic and starting
location" figure), and an animated GIF of a carry and handover.

Built on :class:`world.World` (the scene) and :mod:`render` (caption and PNG writing); PyBullet's
TinyRenderer, headless.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pandas as pd
from PIL import Image, ImageDraw, ImageFont

from ..io.atomic import atomic_write
from .planner import Plan
from .render import FLOOR, caption_lines
from .world import WorkerPosture, World

VIEW_SIZE = 480
# Camera eyes, world frame (worker at the origin facing +x, left = +y): from the worker's left
# side, so worker and robot face each other across the picture; and from above and behind the
# worker's right shoulder, to see both grips on the handles.
VIEWS = {"side": (0.5, 3.1, 1.3), "behind": (-0.9, -2.2, 2.3)}
TARGET = (0.5, 0.0, 0.9)
# The carry starts up to 1.4 m in front of the worker: the GIF looks from further away,
# centred further out.
GIF_CAMERA = {"eye": (0.9, 3.8, 1.4), "target": (0.9, 0.0, 1.0)}
GIF_FRAMES = 40  # carry frames at most (waypoints are skipped evenly beyond that)


class SceneRenderer:
    """A :class:`World` with a floor and cameras. Use as a context manager."""

    def __init__(self, world: World):
        self.world, p = world, world.p
        floor = p.createVisualShape(p.GEOM_BOX, halfExtents=[1.8, 1.5, 0.005], rgbaColor=FLOOR,
                                    physicsClientId=world.client)
        p.createMultiBody(0, baseVisualShapeIndex=floor, basePosition=[0.5, 0, -0.005],
                          physicsClientId=world.client)

    def __enter__(self) -> SceneRenderer:
        return self

    def __exit__(self, *exc) -> None:
        self.world.close()

    def pose(self, location: np.ndarray, robot_q: dict[str, np.ndarray],
             posture: WorkerPosture | None = None, lift: float = 0.0) -> None:
        """Box at ``location`` (worker frame [m]), the robot's base following it with the lift
        at ``lift`` [m], the arms at ``robot_q`` [rad], the worker in ``posture`` (default: at
        rest)."""
        self.world.bring_robot(location, lift)
        self.world.pose_worker(posture)
        for arm, q in robot_q.items():
            self.world.robot.set_arm(arm, q)

    def view(self, eye, size: tuple[int, int] = (VIEW_SIZE, VIEW_SIZE), fov: float = 40.0,
             target=TARGET) -> Image.Image:
        """The scene from ``eye`` toward ``target`` (world frame [m]); ``fov`` vertical [deg]."""
        p, width, height = self.world.p, *size
        view = p.computeViewMatrix(eye, target, [0, 0, 1])
        projection = p.computeProjectionMatrixFOV(fov, width / height, 0.1, 10.0)
        _, _, rgba, _, _ = p.getCameraImage(
            width, height, view, projection, renderer=p.ER_TINY_RENDERER,
            lightDirection=[1, 2, 3], shadow=1, physicsClientId=self.world.client)
        rgb = np.asarray(rgba, dtype=np.uint8).reshape(height, width, 4)[:, :, :3]
        return Image.fromarray(rgb)

    def views(self) -> Image.Image:
        """Every camera of :data:`VIEWS`, side by side."""
        images = [self.view(eye) for eye in VIEWS.values()]
        canvas = Image.new("RGB", (VIEW_SIZE * len(images), VIEW_SIZE), "white")
        for i, image in enumerate(images):
            canvas.paste(image, (i * VIEW_SIZE, 0))
        return canvas


def baseline_caption(row) -> list[str]:
    """Lines under a baseline picture: start, method, the twin's scores, the robot's verdict."""
    head = (f"start ({row['start_x']:+.3f}, {row['start_y']:.3f}, {row['start_z']:.3f}) m -> "
            f"{row['method'].replace('_', ' ')} location")
    robot = (f"robot: carry planned ({row['path_length_m']:.2f} m, clearance "
             f"{100 * row['clearance_m']:.0f} cm)" if row["robot_feasible"] else
             f"robot: cannot serve it ({row['robot_reason']})")
    return [head, *caption_lines(row), robot]


def contact_sheet(cells: list[tuple[Image.Image, list[str]]], path: str | os.PathLike,
                  columns: int = 2, scale: float = 0.5, font_size: int = 13) -> Path:
    """Pictures scaled by ``scale``, each with its short label lines underneath (in a font
    that stays legible at that scale), in rows of ``columns`` (row-major), as a PNG."""
    font = ImageFont.load_default(size=font_size)
    band = 6 + (font_size + 4) * max(len(lines) for _, lines in cells)
    w = max(int(image.width * scale) for image, _ in cells)
    h = max(int(image.height * scale) for image, _ in cells) + band
    rows = -(-len(cells) // columns)
    sheet = Image.new("RGB", (w * columns, h * rows), "white")
    draw = ImageDraw.Draw(sheet)
    for k, (image, lines) in enumerate(cells):
        x, y = (k % columns) * w, (k // columns) * h
        small = image.resize((int(image.width * scale), int(image.height * scale)),
                             Image.Resampling.LANCZOS)
        sheet.paste(small, (x, y))
        for i, line in enumerate(lines):
            draw.text((x + 8, y + small.height + 4 + (font_size + 4) * i), line, fill="black",
                      font=font)
    return atomic_write(path, lambda handle: sheet.save(handle, format="PNG", optimize=True),
                        binary=True)


def short_label(row, number: int) -> list[str]:
    """Two lines for a contact-sheet cell: start and method; scores and the robot's verdict."""
    method = row["method"].replace("_", " ")
    head = (f"start {number} ({row['start_x']:.3f}, {row['start_y']:.3f}, "
            f"{row['start_z']:.3f}): {method}")
    if not row["feasible"]:
        return [head, f"twin infeasible ({row['reason']})"]
    paper = row.get("paper_postural_paper")
    paper = "" if paper is None or pd.isna(paper) else f" (paper {int(paper)})"
    robot = "yes" if row["robot_feasible"] else "no"
    return [head, f"postural {row['paper_postural']}{paper}, REBA {row['reba']}, "
                  f"RULA {row['rula']}; robot {robot}"]


def carry_gif(renderer: SceneRenderer, plan: Plan, posture: WorkerPosture | None,
              path: str | os.PathLike, size: tuple[int, int] = (420, 320),
              reach_frames: int = 8, hold_ms: int = 1200) -> Path:
    """An animated GIF of a planned carry: the box travels along the waypoints (at most
    :data:`GIF_FRAMES` of them, evenly spaced in time), then the worker reaches from rest
    into ``posture`` and holds it.

    Args:
        renderer: the scene.
        plan: a planned carry (with waypoints).
        posture: the worker's posture at the handover (None: stays at rest).
        path: the GIF to write (atomically).
        size: frame width and height [px].
        reach_frames: frames over which the worker moves from rest to ``posture``.
        hold_ms: how long the last frame stays [ms].
    """
    waypoints = plan.waypoints
    times = np.array([w.time for w in waypoints])
    picks = np.unique(np.searchsorted(times, np.linspace(0.0, times[-1], GIF_FRAMES)))
    frames = []
    for i in picks:
        w = waypoints[min(i, len(waypoints) - 1)]
        renderer.pose(w.location, w.q, lift=w.lift)
        frames.append(renderer.view(size=size, **GIF_CAMERA))
    last = waypoints[-1]
    if posture is not None:
        for t in np.linspace(0.0, 1.0, reach_frames + 1)[1:]:
            blended = WorkerPosture(posture.joint_names, t * np.asarray(posture.q))
            renderer.pose(last.location, last.q, blended, lift=last.lift)
            frames.append(renderer.view(size=size, **GIF_CAMERA))
    # One shared palette keeps the file small and the colours steady between frames.
    palette = frames[len(frames) // 2].quantize(colors=96, method=Image.Quantize.MEDIANCUT)
    quantised = [f.quantize(palette=palette, dither=Image.Dither.NONE) for f in frames]
    step_ms = round(1000 * float(times[-1]) / max(1, len(picks) - 1))
    durations = [max(40, step_ms)] * (len(picks) - 1) + [120] * (len(quantised) - len(picks))
    durations.append(hold_ms)
    return atomic_write(path, lambda handle: quantised[0].save(
        handle, format="GIF", save_all=True, append_images=quantised[1:],
        duration=durations[:len(quantised)], loop=0, optimize=True), binary=True)
