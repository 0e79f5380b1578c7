"""Every score of N postures in one call: REBA, RULA and the paper's postural score."""

from __future__ import annotations

import numpy as np

from .paper_score import paper_postural
from .posture import Posture
from .reba import reba
from .rula import rula
from .settings import ScoringSettings

# The headline score columns of the file contracts (docs/architecture.md), in contract order;
# item scores follow them.
OBJECTIVES = ("paper_postural", "reba", "reba_ab", "rula")
"""The headline scores (lower is safer): what a learner can minimise and what every table of
the study reports."""
MAIN_SCORE_COLUMNS = (
    "reba", "reba_table_a", "reba_table_b", "reba_score_a", "reba_score_b", "reba_score_c",
    "reba_action_level", "rula", "paper_postural",
)


def score_postures(posture: Posture,
                   settings: ScoringSettings | None = None) -> dict[str, np.ndarray]:
    """Score N postures with REBA, RULA and the paper's postural score.

    Args:
        posture: the postures to score.
        settings: the choices the REBA/RULA sources leave open; defaults if omitted.

    Returns:
        Named (N,) int8 arrays: :data:`MAIN_SCORE_COLUMNS` first, then ``reba_ab`` and every
        item score (``reba_*``, ``rula_*``, ``paper_*``).
    """
    settings = settings or ScoringSettings()
    items = {**reba(posture, settings), **rula(posture, settings), **paper_postural(posture)}
    ordered = {name: items.pop(name) for name in MAIN_SCORE_COLUMNS}
    return {**ordered, **items}


SCORE_COLUMNS: tuple[str, ...] = tuple(
    score_postures(Posture.random(1, np.random.default_rng(0)))
)
