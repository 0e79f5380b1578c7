"""Every score of N postures in one call: REBA, RULA and the paper's postural score."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import ConfigError
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


SCORERS = {"paper": lambda p, s: paper_postural(p), "reba": reba, "rula": rula}
"""Each scorer by the prefix of the columns it gives."""


def score_postures(posture: Posture, settings: ScoringSettings | None = None,
                   names: Sequence[str] | None = None) -> dict[str, np.ndarray]:
    """Score N postures with REBA, RULA and the paper's postural score.

    Args:
        posture: the postures to score.
        settings: the choices the REBA/RULA sources leave open; defaults if omitted.
        names: only these columns, in this order, running only the scorers that give them (a
            search that ranks by one score skips the others' work); every column if omitted.

    Returns:
        Named (N,) int8 arrays: :data:`MAIN_SCORE_COLUMNS` first, then ``reba_ab`` and every
        item score (``reba_*``, ``rula_*``, ``paper_*``); or the columns ``names``.

    Raises:
        ConfigError: a name no scorer gives (one line).
    """
    settings = settings or ScoringSettings()
    if names is None:
        items = {**reba(posture, settings), **rula(posture, settings),
                 **paper_postural(posture)}
        ordered = {name: items.pop(name) for name in MAIN_SCORE_COLUMNS}
        return {**ordered, **items}
    found: dict[str, np.ndarray] = {}
    for family in sorted({name.split("_")[0] for name in names} & SCORERS.keys()):
        found |= SCORERS[family](posture, settings)
    for name in names:
        if name not in found:
            raise ConfigError(f"score = {name!r} is not allowed (use a column of "
                              "score_postures)")
    return {name: found[name] for name in names}


SCORE_COLUMNS: tuple[str, ...] = tuple(
    score_postures(Posture.random(1, np.random.default_rng(0)))
)
