"""The transfer moment: on synthetic handovers whose transfer frame is known by construction,
the rule finds it whatever the object's tracked point's offset from each grasp, and does not
end the giver's hold on a few noisy frames."""

from __future__ import annotations

import numpy as np
import pytest

from ergohandover.study.people.transfer import STEP, Transfer, TransferError, transfer

FPS = 30.0
CONTACT, RELEASE = 50, 75
"""By construction: the receiver's hand takes hold at frame 50, the giver's lets go at 75."""


def handover(receiving: int = 1, seed: int = 0, noise_m: float = 0.005):
    """Tracks of one synthetic handover: the giver holds the object still, then carries it
    toward the receiver, who walks up; both carry it together from CONTACT; the giver lets go
    at RELEASE and pulls back while the receiver walks on with it. The object's tracked point
    lies 0.28 m from the giver's hand and 0.15 m from the receiver's, as a marker would.
    Returns (object (T, 3), receiver hands (T, 2, 3), giver hands (T, 2, 3))."""
    rng = np.random.default_rng(seed)
    t = np.arange(130, dtype=float)
    # The object: still, then toward the meeting point, then along -x with the receiver.
    x = np.interp(t, [0, 20, CONTACT, 129], [0.5, 0.5, 0.3, -0.9])
    obj = np.column_stack([x, np.full_like(t, -0.6), np.full_like(t, 1.3)])
    giver_grip = np.array([0.2, 0.07, 0.18])  # object minus hand while the giver holds it
    receiver_grip = np.array([0.11, 0.04, 0.10])
    giver = np.empty((130, 2, 3))
    giver[:, 1] = obj - giver_grip
    back = np.clip(t - RELEASE, 0, None)[:, None] * np.array([0.03, 0.0, -0.01])
    giver[RELEASE:, 1] = obj[RELEASE] - giver_grip + back[RELEASE:]  # lets go, pulls back
    giver[:, 0] = np.array([0.0, 0.2, 0.8])  # the free hand hangs still
    walk = obj[CONTACT] - receiver_grip + np.clip(CONTACT - t, 0, None)[:, None] * np.array(
        [0.03, -0.004, -0.002])  # walking up from +x
    receiver = np.empty((130, 2, 3))
    receiver[:, receiving] = np.where((t >= CONTACT)[:, None], obj - receiver_grip, walk)
    # The free hand swings with the body: with the walk, not with the object before contact.
    body = np.where((t >= CONTACT)[:, None], obj - receiver_grip, walk)
    receiver[:, 1 - receiving] = body + np.array([0.1, 0.4 * (1 if receiving == 0 else -1), -0.4])
    jitter = lambda x: x + rng.normal(0.0, noise_m, x.shape)  # noqa: E731
    return jitter(obj), jitter(receiver), jitter(giver)


@pytest.mark.parametrize("receiving", [0, 1])
@pytest.mark.parametrize("seed", range(5))
def test_the_rule_finds_the_givers_release_and_the_receiving_hand(receiving, seed):
    found = transfer(*handover(receiving, seed), FPS)
    assert isinstance(found, Transfer)
    assert RELEASE - STEP <= found.frame <= RELEASE + 3, found  # a velocity spans 2 * STEP
    assert found.hand == receiving
    assert found.distance == pytest.approx(np.linalg.norm([0.11, 0.04, 0.10]), abs=0.03)


def test_a_few_noisy_frames_do_not_end_the_givers_hold():
    obj, receiver, giver = handover()
    giver[60:64, 1] += np.array([0.0, 0.0, 0.15])  # the giver's hand point jumps for 4 frames
    assert RELEASE - STEP <= transfer(obj, receiver, giver, FPS).frame <= RELEASE + 3
    obj, receiver, giver = handover()
    giver[60:, 1] += np.array([0.0, 0.0, 0.01]) * np.arange(70)[:, None]  # it lets go at 60
    assert 60 - STEP <= transfer(obj, receiver, giver, FPS).frame <= 63


def test_unseen_hands_are_left_out():
    obj, receiver, giver = handover()
    receiver[30:40] = np.nan
    giver[90:100, 1] = np.nan
    assert RELEASE - STEP <= transfer(obj, receiver, giver, FPS).frame <= RELEASE + 3


def test_tracks_without_a_transfer_are_refused_saying_why():
    obj, receiver, giver = handover()
    with pytest.raises(TransferError, match=r"never moves with a receiver's hand within 0\.5 m"):
        transfer(obj, receiver + 5.0, giver, FPS)  # the receiver never comes near
    with pytest.raises(TransferError, match="from the first frame on"):
        transfer(obj[RELEASE + 5:], receiver[RELEASE + 5:], giver[RELEASE + 5:], FPS)
