"""How far each measured angle of a posture is from changing a score: the margin to the nearest
band edge, found by moving one angle at a time (so it holds for every scorer, with its own band
edges and table look-ups, without restating them).

A margin of 0.5° on the trunk's twist says the paper's score changes if the twist is measured
half a degree off; a location whose smallest margin is large keeps its score under small errors.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from ..ergonomics import Posture, ScoringSettings, score_postures
from .posture_error import ANGLE_COLUMNS, SCORES

STEP_DEG = 0.25
"""The resolution of a margin [deg]."""
REACH_DEG = 30.0
"""The largest move tried [deg]: beyond it a margin is reported as missing (no change)."""
CHUNK_ROWS = 1_000_000


def _moves() -> np.ndarray:
    """The signed moves tried, smallest magnitude first within each sign."""
    steps = np.arange(STEP_DEG, REACH_DEG + STEP_DEG / 2, STEP_DEG)
    return np.concatenate([steps, -steps])


def margins(posture: Posture, scores: Sequence[str] = SCORES,
            columns: Sequence[str] = ANGLE_COLUMNS,
            settings: ScoringSettings | None = None) -> dict[str, np.ndarray]:
    """The margin of each angle of each posture to a change of each score.

    Returns:
        score -> (N, len(columns)) the smallest move [deg] of that angle alone (either sign)
        that changes the score; NaN when no move within :data:`REACH_DEG` does. Moves are
        clipped to the table's ±180°.
    """
    moves = _moves()
    block = len(columns) * len(moves)  # rows per posture
    per_chunk = max(1, CHUNK_ROWS // block)
    nominal = score_postures(posture, settings, names=scores)
    out = {s: np.empty((posture.n, len(columns))) for s in scores}
    for start in range(0, posture.n, per_chunk):
        index = np.arange(start, min(start + per_chunk, posture.n))
        rows = {}
        for name, values in posture.take(index).items():
            repeated = np.repeat(values, block)
            if name in columns:
                shift = np.zeros((len(columns), len(moves)))
                shift[list(columns).index(name)] = moves
                repeated = np.clip(repeated + np.tile(shift.ravel(), len(index)), -180, 180)
            rows[name] = repeated
        moved = score_postures(Posture(rows), settings, names=scores)
        for s in scores:
            changed = (moved[s].reshape(len(index), len(columns), len(moves))
                       != nominal[s][index, None, None])
            size = np.where(changed, np.abs(moves), np.inf).min(axis=2)
            out[s][index] = np.where(np.isinf(size), np.nan, size)
    return out


def margin_table(posture: Posture, names: Sequence[str], scores: Sequence[str] = SCORES,
                 settings: ScoringSettings | None = None) -> pd.DataFrame:
    """One row per posture, angle and score: ``location, angle, value, score, margin_deg``
    (the posture's own angle [deg] and its margin; empty when no move within
    :data:`REACH_DEG` changes the score)."""
    found = margins(posture, scores, settings=settings)
    frames = []
    for s in scores:
        frames.append(pd.DataFrame({
            "location": np.repeat(list(names), len(ANGLE_COLUMNS)),
            "angle": np.tile(ANGLE_COLUMNS, posture.n),
            "value": np.stack([posture[c] for c in ANGLE_COLUMNS], axis=1).ravel(),
            "score": s, "margin_deg": found[s].ravel()}))
    return pd.concat(frames, ignore_index=True)


def smallest_margin(posture: Posture, score: str,
                    settings: ScoringSettings | None = None) -> np.ndarray:
    """(N,) each posture's smallest margin over its angles for one score [deg]
    (:data:`REACH_DEG` when no angle's move changes it)."""
    found = margins(posture, (score,), settings=settings)[score]
    return np.nan_to_num(np.nanmin(np.where(np.isnan(found), REACH_DEG, found), axis=1),
                         nan=REACH_DEG)
