"""The moment an object changes hands, from the tracks of the object and of both people's hands.

**The rule.** The transfer frame is the first frame from which, for at least ``hold_s`` seconds,
the object moves with the receiver's hand and no longer with the giver's: its velocity differs
from the giver's hand's by at least ``margin_mps`` more than from the receiving hand's, and that
hand is within ``reach_m`` of it.
Velocities, not distances, because an object is tracked at a marker or a centre that lies
some way from either grasp (in Kim et al.'s recordings the marker sits about 0.28 m from the
giver's hand point and 0.15 m from the receiver's), so that the distances to the two hands
carry offsets of their own while an object held by a hand moves with it whatever the offset.
While both people hold the object it moves with both (their velocities differ by the tracking
noise, far below the margin); the frame the rule finds is where the giver's hand stops carrying
it: the giver's release. It is the track-based counterpart of the grip-force crossover
(the taker's grip exceeds the giver's) that the Handovers@RPL derivation uses
(``experiments/tools/derive_handover_reference.py``). The velocities are central differences
over ``2 * step`` frames, their mismatches smoothed by a running median of ``window`` frames, and
the ``hold_s`` run keeps a few noisy frames (a hand point jumping, as markerless tracking does)
from ending the giver's hold early.

The receiving hand is the receiver's hand nearer the object at the transfer frame (a walking
receiver's free hand moves with the body, and so with the object, too).
"""

from __future__ import annotations

import warnings
from typing import NamedTuple

import numpy as np

from ...errors import ErgohandoverError

HOLD_S = 0.3
"""How long the object must move with the receiver's hand for the transfer to count [s]."""
REACH_M = 0.5
"""How near the object a hand that holds it is at most [m] (a marker's offset from the grasp
included)."""
MARGIN_MPS = 0.1
"""How much better the receiver's hand must follow the object than the giver's [m/s]: well above
the velocity noise of tracked points (5 mm of position noise gives about 0.05 m/s here) and
below any deliberate hand motion."""
WINDOW = 5
"""Frames of the running median the velocity mismatches are smoothed with (odd)."""
STEP = 2
"""Half the frames a velocity is taken over."""


class TransferError(ErgohandoverError, ValueError):
    """Tracks in which no transfer can be found; the message is one line saying why."""


class Transfer(NamedTuple):
    """Where in the tracks the object changed hands.

    Attributes:
        frame: the transfer frame (0-based).
        hand: the receiving hand, 0 or 1 (the order of ``receiver_hands``).
        distance: the receiving hand's distance to the object there [m].
    """

    frame: int
    hand: int
    distance: float


def running_median(values: np.ndarray, window: int) -> np.ndarray:
    """(T, ...) values smoothed along the first axis by a centred running median of ``window``
    frames (the ends take the median of the frames there are); NaN frames are left out."""
    half = window // 2
    padded = np.pad(values, [(half, half)] + [(0, 0)] * (values.ndim - 1),
                    constant_values=np.nan)
    frames = np.lib.stride_tricks.sliding_window_view(padded, window, axis=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN window stays NaN
        return np.nanmedian(frames, axis=-1)


def velocity(track: np.ndarray, fps: float, step: int = STEP) -> np.ndarray:
    """(T, ..., 3) central-difference velocities [m/s] (NaN within ``step`` of either end)."""
    out = np.full(track.shape, np.nan)
    out[step:-step] = (track[2 * step:] - track[:-2 * step]) * fps / (2 * step)
    return out


def transfer(object_track: np.ndarray, receiver_hands: np.ndarray, giver_hands: np.ndarray,
             fps: float, hold_s: float = HOLD_S, reach_m: float = REACH_M,
             margin_mps: float = MARGIN_MPS, window: int = WINDOW) -> Transfer:
    """The transfer frame of one handover (the module's rule).

    Args:
        object_track: (T, 3) the object's tracked point [m].
        receiver_hands: (T, 2, 3) the receiver's two hand points [m] (NaN where not seen).
        giver_hands: (T, 2, 3) the giver's two hand points [m].
        fps: frames per second of the tracks.
        hold_s: how long the object must move with the receiver's hand [s].
        reach_m: how near the object a holding hand is at most [m].
        margin_mps: how much better the receiver's hand must follow the object [m/s].
        window: the running median's frames.

    Raises:
        TransferError: the object never moves with the receiver's hand for ``hold_s``, or does
            from the first frame on (no giver's hold is seen).
    """
    obj = np.asarray(object_track, dtype=np.float64)
    receiver, giver = np.asarray(receiver_hands, float), np.asarray(giver_hands, float)
    moving = velocity(obj, fps)[:, None]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # frames with no hand seen: NaN
        to_receiver = running_median(np.linalg.norm(velocity(receiver, fps) - moving, axis=2),
                                     window)  # (T, 2)
        to_giver = np.nanmin(running_median(
            np.linalg.norm(velocity(giver, fps) - moving, axis=2), window), axis=1)
        near = np.linalg.norm(receiver - obj[:, None], axis=2) <= reach_m
        mismatch = np.where(near, to_receiver, np.inf)
        best = np.nanmin(mismatch, axis=1)
    with_receiver = best + margin_mps < to_giver  # NaN compares False: unseen holds nothing
    hold = max(1, round(hold_s * fps))
    run = np.convolve(with_receiver.astype(int), np.ones(hold, dtype=int), mode="valid") == hold
    starts = np.flatnonzero(run)
    if starts.size == 0:
        raise TransferError(f"the object never moves with a receiver's hand within {reach_m:g} m "
                            f"for {hold_s:g} s ({hold} frames at {fps:g} Hz)")
    frame = int(starts[0])
    if not (~with_receiver[:frame] & np.isfinite(to_giver[:frame])).any():
        raise TransferError("the object moves with the receiver's hand from the first frame on "
                            "(the giver's hold is not in the recording)")
    distance = np.linalg.norm(receiver[frame] - obj[frame], axis=1)
    hand = int(np.nanargmin(distance))
    return Transfer(frame, hand, float(distance[hand]))
