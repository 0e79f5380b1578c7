"""Pure posture scoring (numpy only, no simulator): REBA, RULA and the paper's postural score.

Typical use::

    from ergohandover.ergonomics import Posture, score_postures
    scores = score_postures(Posture(columns))   # columns: name -> (N,) array
    scores["reba"], scores["rula"], scores["paper_postural"]
"""

from .paper_score import paper_postural
from .posture import POSTURE_COLUMNS, REQUIRED_COLUMNS, Posture, PostureError
from .reba import reba
from .rula import rula
from .scores import MAIN_SCORE_COLUMNS, OBJECTIVES, SCORE_COLUMNS, score_postures
from .settings import ScoringSettings, SettingsError

__all__ = [
    "MAIN_SCORE_COLUMNS",
    "OBJECTIVES",
    "POSTURE_COLUMNS",
    "REQUIRED_COLUMNS",
    "SCORE_COLUMNS",
    "Posture",
    "PostureError",
    "ScoringSettings",
    "SettingsError",
    "paper_postural",
    "reba",
    "rula",
    "score_postures",
]
