"""The defaults every command shares with the study, read from where they are decided.

A flag that two commands take (``--boundary``, ``--step``, ``--percentile``, ``--gaze``, ...) has
one default, the study's: the study's typed configuration (:mod:`ergohandover.study.config`) is
where each is reasoned about, and a landscape that ``sweep`` puts in the cache is then the one
``train``, ``baseline`` and the study look for. What the study leaves to the model (the posture
solver, the trunk-angle reference) is the model's own default. Nothing here is a literal copy
of a number held elsewhere.
"""

from __future__ import annotations

import csv
import dataclasses
import inspect
from pathlib import Path
from typing import Any

from ..envs.handover_env import HandoverEnv
from ..errors import ErgohandoverError
from ..search.qlearning import QLearningConfig
from ..study.baselines.config import BaselinesConfig
from ..study.config import StudyConfig
from ..study.landscape.config import LandscapeConfig
from ..study.learning.config import LearningConfig, Target
from ..study.robustness.config import RobustnessConfig
from ..study.script import CONFIGS, ROOT
from ..twin.evaluate import Evaluator


def field_default(cls: type, name: str) -> Any:
    """The default of dataclass ``cls``'s field ``name`` (also one made by a factory)."""
    field = next(f for f in dataclasses.fields(cls) if f.name == name)
    if field.default_factory is not dataclasses.MISSING:
        return field.default_factory()
    return field.default


BOUNDARY: str = field_default(LandscapeConfig, "boundary")
STEP: float = field_default(LandscapeConfig, "step")
GAZE: str = field_default(LandscapeConfig, "gaze")
PERCENTILE: str = field_default(Target, "worker")
OBJECTIVE: str = field_default(Target, "objective")
EPISODE_END: str = field_default(LearningConfig, "episode_end")
SEED: int = field_default(BaselinesConfig, "seed")
"""The seed of one command run (the carry planner's, as the study's baselines use it; a learning
run's own seed, which the study instead spawns per run from ``learning.seed``)."""
ANGLE_SD: float = field_default(RobustnessConfig, "robust_sd")
"""The posture error's SD [deg] of a robust search, and of ``robustness`` when none is given."""
DRAWS: int = field_default(RobustnessConfig, "draws")
SOLVER: str = field_default(Evaluator, "solver")
TRUNK_REFERENCE: str = field_default(Evaluator, "trunk_reference")
TEMPERATURE: str = field_default(QLearningConfig, "temperature")
PAPER_TARGET: float = inspect.signature(HandoverEnv).parameters["target"].default
"""The paper's episode-end score (the environment's default ``target``)."""

LANDSCAPE_STATS = Path("results") / "landscape" / "stats.csv"
"""Where the study records the default landscape's statistics (relative to the checkout)."""
PAPER_CONFIG = (CONFIGS / "paper.json").relative_to(ROOT)
"""The study's configuration of the paper's own protocol (relative to the checkout)."""


def recorded_minimum(score: str) -> float | None:
    """The twin's minimum of ``score`` on the default grid, as the study computed and recorded
    it, or None outside a checkout with results (an installed package)."""
    try:
        with open(ROOT / LANDSCAPE_STATS, newline="") as handle:
            rows = {row["score"]: row for row in csv.DictReader(handle)}
        return float(rows[score]["min"])
    except (OSError, KeyError, ValueError):
        return None


def paper_wall_caps() -> tuple[float, ...] | None:
    """The paper's wall-clock caps [s] as the study's paper protocol runs them, or None outside
    a checkout."""
    try:
        return StudyConfig.load(ROOT / PAPER_CONFIG).learning.wall_caps_s
    except (OSError, ErgohandoverError):
        return None
