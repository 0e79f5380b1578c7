"""The shoulders' neutral a capture's shoulder raise is measured from: each side's clavicle
slope when the person stands relaxed.

A clavicle read from keypoints runs from a neck base or clavicle point to the shoulder, points
each format and rig places in its own way, so its slope at rest differs between formats and
people by more than the 10° at which a raised shoulder counts. The neutral is, in order of
preference:

- a frame of the capture in which the person stands relaxed (``--neutral-frame``): each side's
  own slope, in the format's own geometry;
- a BVH file's rest pose (its OFFSETs with no rotation): the rig's own body;
- the body model's slope for the worker the flags describe (``--stature``, ``--sex``, ...);
- the body model's for the 50th-percentile man.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..errors import ErgohandoverError
from .angles import NEUTRAL_CLAVICLE_DEG, clavicle_slope_deg, clavicle_slopes
from .formats import SIDES, KeypointFormat


class NeutralFrameError(ErgohandoverError, ValueError):
    """A neutral frame the file lacks, or in which the shoulders are not seen; one line."""


class Neutral(NamedTuple):
    """Each side's clavicle slope at rest [deg] and, for the summary line, where it is from."""

    degrees: dict[str, float]
    said: str
    hint: str = ""

    def note(self) -> str:
        """The summary line's words: the slopes and their source."""
        left, right = (self.degrees[side] for side in SIDES)
        slopes = f"{left:.1f}°" if left == right else f"left {left:.1f}°, right {right:.1f}°"
        return f"shoulder raise from {self.said} ({slopes}{self.hint})"


def frame_row(frames: np.ndarray, number: int | None) -> int | None:
    """The first row of frame ``number`` (None: not asked for, or not in ``frames``): the
    frame whose slopes are the neutral, whether a file is read whole or in parts."""
    rows = np.flatnonzero(frames == number) if number is not None else []
    return int(rows[0]) if len(rows) else None


def default_neutral() -> Neutral:
    """The 50th-percentile man's slope, when nothing says the person's own."""
    return Neutral(dict.fromkeys(SIDES, NEUTRAL_CLAVICLE_DEG),
                   "the 50th-percentile man's clavicle slope",
                   "; --neutral-frame N or the worker's --stature/--sex give this person's")


def body_neutral(body, said: str) -> Neutral:
    """The body model's slope for ``body`` (a :class:`~ergohandover.twin.BodySpec`)."""
    return Neutral(dict.fromkeys(SIDES, clavicle_slope_deg(body)), said)


def rest_neutral(fmt: KeypointFormat, up: str) -> Neutral | None:
    """A rig's rest pose's slopes (None for a format without one, or where it does not show
    both clavicles)."""
    if not fmt.rest:
        return None
    slopes = clavicle_slopes(np.array([fmt.rest], dtype=np.float64), fmt, up)
    found = {side: float(slopes[side][0]) for side in SIDES}
    if not all(np.isfinite(v) for v in found.values()):
        return None
    return Neutral(found, "the clavicle slopes of the rig's rest pose")


def frame_neutral(frames: np.ndarray, points: np.ndarray | None, number: int,
                  fmt: KeypointFormat, up: str, what: str) -> Neutral:
    """Frame ``number``'s slopes.

    Args:
        frames: every frame number of the file (for the message).
        points: (J, 3) points of that frame, None when the file lacks it.
        number: the frame, as ``--neutral-frame`` gave it.
        fmt, up: the file's format and up axis.
        what: the file, as typed.

    Raises:
        NeutralFrameError: the file lacks the frame, or its shoulders are not seen in it.
    """
    flag = f"--neutral-frame {number}"
    if points is None:
        shown = f"frames {frames.min()}-{frames.max()}" if len(frames) else "no frames"
        raise NeutralFrameError(f"{flag}: {what} has {shown}")
    slopes = clavicle_slopes(points[None], fmt, up)
    unseen = [side for side in SIDES if not np.isfinite(slopes[side][0])]
    if unseen:
        why = ("the format does not measure shoulder raise" if any(
            f"{side}_shoulder_raise" in fmt.unseen for side in SIDES)
            or not {"neck_base", "left_clavicle"} & set(fmt.landmarks)
            else "a point of the clavicle or shoulder is missing there")
        raise NeutralFrameError(f"{flag}: the {' and '.join(unseen)} shoulder "
                                f"{'is' if len(unseen) == 1 else 'are'} not seen in frame "
                                f"{number} of {what} ({why})")
    return Neutral({side: float(slopes[side][0]) for side in SIDES},
                   f"the clavicle slopes of frame {number}")
