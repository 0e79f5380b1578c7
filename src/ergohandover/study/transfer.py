"""The moment an object changes hands, from the tracks of the object and of both people's hands.

**The rule.** The transfer frame is the first frame from which the object stays nearer the
receiver's nearer hand than the giver's nearer hand for at least ``hold_s`` seconds. In a
handover both people hold the object for a while; while the giver alone holds it, it moves with
the giver's hand, and afterwards with the receiver's: the object's distances to the two hands
cross in the shared hold. It is the track-based counterpart of the grip-force crossover (the
taker's grip exceeds the giver's) that the Handovers@RPL derivation uses
(``experiments/tools/derive_handover_reference.py``), needs no force sensor, and has no
distance threshold that depends on the object's size or the camera's noise. Requiring the
crossing to hold for ``hold_s`` keeps a single noisy frame (a hand point jumping for one frame,
as markerless tracking does) from ending the giver's hold early; the distances are first
smoothed by a running median of ``window`` frames for the same reason.

The receiving hand is the receiver's hand nearer the object at the transfer frame.
"""

from __future__ import annotations

import warnings
from typing import NamedTuple

import numpy as np

from ..errors import ErgohandoverError

HOLD_S = 0.2
"""How long the object must stay nearer the receiver's hand for the crossing to count [s]."""
WINDOW = 5
"""Frames of the running median the distances are smoothed with (odd)."""


class TransferError(ErgohandoverError, ValueError):
    """Tracks in which no transfer can be found; the message is one line saying why."""


class Transfer(NamedTuple):
    """Where in the tracks the object changed hands.

    Attributes:
        frame: the transfer frame (0-based).
        hand: the receiving hand, 0 or 1 (the order of ``receiver_hands``).
        receiver_distance: the receiving hand's distance to the object there [m] (smoothed).
        giver_distance: the giver's nearer hand's distance to the object there [m] (smoothed).
    """

    frame: int
    hand: int
    receiver_distance: float
    giver_distance: float


def running_median(values: np.ndarray, window: int) -> np.ndarray:
    """(T,) values smoothed by a centred running median of ``window`` frames (the ends take the
    median of the frames there are); NaN frames are left out of each median."""
    half = window // 2
    padded = np.pad(values, half, mode="constant", constant_values=np.nan)
    frames = np.lib.stride_tricks.sliding_window_view(padded, window)  # (T, window)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN window stays NaN
        return np.nanmedian(frames, axis=1)


def transfer(object_track: np.ndarray, receiver_hands: np.ndarray, giver_hands: np.ndarray,
             fps: float, hold_s: float = HOLD_S, window: int = WINDOW) -> Transfer:
    """The transfer frame of one handover (the module's rule).

    Args:
        object_track: (T, 3) the object's centre [m].
        receiver_hands: (T, 2, 3) the receiver's two hand points [m] (NaN where not seen).
        giver_hands: (T, 2, 3) the giver's two hand points [m].
        fps: frames per second of the tracks.
        hold_s: how long the crossing must hold [s].
        window: the running median's frames.

    Raises:
        TransferError: the object is never nearer the receiver for ``hold_s``, or it starts
            there (no giver's hold is seen).
    """
    object_track = np.asarray(object_track, dtype=np.float64)
    to_receiver = np.linalg.norm(np.asarray(receiver_hands) - object_track[:, None], axis=2)
    to_giver = np.linalg.norm(np.asarray(giver_hands) - object_track[:, None], axis=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a frame with no hand seen: NaN
        receiver = running_median(np.nanmin(to_receiver, axis=1), window)
        giver = running_median(np.nanmin(to_giver, axis=1), window)
    nearer = receiver < giver  # NaN compares False: an unseen frame holds nothing
    hold = max(1, round(hold_s * fps))
    # Frames from which the receiver is nearer for `hold` frames in a row.
    run = np.convolve(nearer.astype(int), np.ones(hold, dtype=int), mode="valid") == hold
    starts = np.flatnonzero(run)
    if starts.size == 0:
        raise TransferError(f"the object is never nearer the receiver's hand for {hold_s:g} s "
                            f"({hold} frames at {fps:g} Hz)")
    frame = int(starts[0])
    if frame == 0 or not (~nearer[:frame] & np.isfinite(giver[:frame])).any():
        raise TransferError("the object is nearer the receiver's hand from the first frame on "
                            "(the giver's hold is not in the recording)")
    hand = int(np.nanargmin(to_receiver[frame]))
    return Transfer(frame, hand, float(receiver[frame]), float(giver[frame]))
