"""Measured people in: postures captured as 3D keypoints (pose estimators, motion capture) turned
into the Posture columns by the worksheets' definitions, with what a capture cannot see stated
as uncertainty in the scores.

Typical use::

    from ergohandover.capture import capture, capture_scores, keypoint_format
    captured = capture(points, keypoint_format("h36m17"), up="-y")  # points: (N, 17, 3) [m]
    scores = capture_scores(captured)   # reba, reba_lo, reba_hi, rula, ..., paper_postural_hi
"""

from .captured import MODES, Captured, capture, capture_scores
from .formats import FORMATS, FormatError, KeypointFormat, keypoint_format

__all__ = ["FORMATS", "MODES", "Captured", "FormatError", "KeypointFormat", "capture",
           "capture_scores", "keypoint_format"]
