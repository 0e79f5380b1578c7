"""Gymnasium environments: :class:`HandoverEnv`, registered as ``ergohandover/Handover-v0``, and
:class:`ContinuousHandoverEnv` (moves of up to a few cells per axis, for SAC), registered as
``ergohandover/ContinuousHandover-v0``, when this package is imported (as Gymnasium environment
packages do), so that after ``import ergohandover.envs``,
``gymnasium.make("ergohandover/Handover-v0", landscape=FILE)`` builds it."""

from __future__ import annotations

import gymnasium

from .continuous_env import ContinuousHandoverEnv
from .handover_env import ACTIONS, EPISODE_STEPS, HandoverEnv
from .scores import OBJECTIVES, ArrayScores, LandscapeScores, OnlineScores, ScoreSource

ENV_ID = "ergohandover/Handover-v0"
CONTINUOUS_ENV_ID = "ergohandover/ContinuousHandover-v0"

__all__ = ["ACTIONS", "CONTINUOUS_ENV_ID", "ENV_ID", "EPISODE_STEPS", "OBJECTIVES",
           "ArrayScores", "ContinuousHandoverEnv", "HandoverEnv", "LandscapeScores", "OnlineScores",
           "ScoreSource", "register"]


def register() -> str:
    """Register :data:`ENV_ID` and :data:`CONTINUOUS_ENV_ID` with Gymnasium (each truncated at
    :data:`EPISODE_STEPS`); idempotent.

    ``gymnasium.make(ENV_ID, scores=...)`` (or ``landscape=FILE``) then builds the env.

    Returns:
        :data:`ENV_ID`.
    """
    if ENV_ID not in gymnasium.registry:
        gymnasium.register(id=ENV_ID, entry_point="ergohandover.envs.handover_env:HandoverEnv",
                           max_episode_steps=EPISODE_STEPS)
    if CONTINUOUS_ENV_ID not in gymnasium.registry:
        gymnasium.register(id=CONTINUOUS_ENV_ID,
                           entry_point="ergohandover.envs.continuous_env:ContinuousHandoverEnv",
                           max_episode_steps=EPISODE_STEPS)
    return ENV_ID


register()
