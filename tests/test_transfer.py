"""The transfer moment: on synthetic handovers whose transfer frame is known by construction,
the rule finds it, and does not end the giver's hold on a noisy frame."""

from __future__ import annotations

import numpy as np
import pytest

from ergohandover.study.transfer import Transfer, TransferError, transfer

FPS = 30.0
SHARED = (45, 55)
"""The frames both people hold the object; by construction the hold passes from the giver to
the receiver at the middle, frame 50."""


def handover(receiving: int = 1, seed: int = 0, noise_m: float = 0.005):
    """Tracks of one synthetic handover: the giver carries the object to the meeting point,
    both hold it while the giver's grip opens and the receiver's closes, then the receiver takes
    it away. Returns (object (T, 3), receiver hands (T, 2, 3), giver hands (T, 2, 3))."""
    rng = np.random.default_rng(seed)
    t = np.arange(120)
    meet = np.array([0.5, 0.0, 1.0])
    start, end = np.array([1.0, 0.0, 1.0]), np.array([0.2, 0.1, 1.0])
    a, b = SHARED
    # The object: with the giver until the shared hold, still in it, with the receiver after.
    carry = np.clip(t / a, 0, 1)[:, None]
    away = np.clip((t - b) / (119 - b), 0, 1)[:, None]
    obj = start + carry * (meet - start) + away * (end - meet)
    # Each hand's distance to the object: 3 cm while it holds, opening or closing over the
    # shared hold (they cross at its middle), far before or after.
    opening = np.interp(t, [0, a, b, b + 10, 119], [0.03, 0.03, 0.12, 0.4, 0.6])
    closing = np.interp(t, [0, a - 20, a, b, 119], [0.8, 0.5, 0.12, 0.03, 0.03])
    receiver = np.empty((120, 2, 3))
    giver = np.empty((120, 2, 3))
    receiver[:, receiving] = obj + closing[:, None] * np.array([-1.0, 0.0, 0.0])
    receiver[:, 1 - receiving] = obj + np.array([-0.3, 0.4 * (1 if receiving else -1), -0.5])
    giver[:, 1] = obj + opening[:, None] * np.array([1.0, 0.0, 0.0])
    giver[:, 0] = obj + np.array([0.3, 0.4, -0.5])
    jitter = lambda x: x + rng.normal(0.0, noise_m, x.shape)  # noqa: E731
    return jitter(obj), jitter(receiver), jitter(giver)


@pytest.mark.parametrize("receiving", [0, 1])
@pytest.mark.parametrize("seed", range(5))
def test_the_rule_finds_the_middle_of_the_shared_hold_and_the_receiving_hand(receiving, seed):
    found = transfer(*handover(receiving, seed), FPS)
    assert isinstance(found, Transfer)
    assert abs(found.frame - 50) <= 1, found
    assert found.hand == receiving
    assert found.receiver_distance < found.giver_distance + 0.02


def test_a_noisy_frame_or_three_do_not_end_the_givers_hold():
    obj, receiver, giver = handover()
    receiver[20:23, 1] = obj[20:23]  # the receiving hand's point jumps onto the object
    assert abs(transfer(obj, receiver, giver, FPS).frame - 50) <= 1
    receiver[20:35, 1] = obj[20:35]  # 0.5 s: a hold of the object, not noise
    assert transfer(obj, receiver, giver, FPS).frame < 25


def test_unseen_hands_are_left_out():
    obj, receiver, giver = handover()
    receiver[30:40] = np.nan
    giver[60:70, 1] = np.nan
    assert abs(transfer(obj, receiver, giver, FPS).frame - 50) <= 1


def test_tracks_without_a_transfer_are_refused_saying_why():
    obj, receiver, giver = handover()
    with pytest.raises(TransferError, match=r"never nearer the receiver's hand for 0\.2 s"):
        transfer(obj, receiver + 5.0, giver, FPS)  # the receiver never comes near
    with pytest.raises(TransferError, match="from the first frame on"):
        transfer(obj[60:], receiver[60:], giver[60:], FPS)
