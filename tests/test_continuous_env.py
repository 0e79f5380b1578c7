"""The continuous-action env (Gymnasium's checker, moves, reward, registration) and SAC on it,
directly and through ``train``."""

from __future__ import annotations

import dataclasses

import gymnasium
import numpy as np
import pandas as pd
import pytest
from gymnasium.utils.env_checker import check_env
from synthetic import CENTRE, bowl_landscape, flat

from ergohandover.cli import main
from ergohandover.envs import (
    CONTINUOUS_ENV_ID,
    ContinuousHandoverEnv,
    HandoverEnv,
    LandscapeScores,
)
from ergohandover.errors import ConfigError
from ergohandover.search import Budget, make, run
from ergohandover.search.sac import SACConfig, run_sac


def bowl_continuous(**kwargs) -> ContinuousHandoverEnv:
    return ContinuousHandoverEnv(LandscapeScores(bowl_landscape()), **kwargs)


def test_the_env_passes_gymnasiums_checker():
    check_env(bowl_continuous(), skip_render_check=True)


def test_gymnasium_makes_it_with_the_registered_truncation():
    env = gymnasium.make(CONTINUOUS_ENV_ID, scores=LandscapeScores(bowl_landscape()))
    assert env.spec.max_episode_steps == 10_000
    assert isinstance(env.unwrapped, ContinuousHandoverEnv)


@pytest.mark.parametrize(("start", "action", "expected"), [
    (CENTRE, (1.0, 0.0, 0.0), (5, 3, 3)),      # +2 cells (max_move) along x
    ((5, 3, 3), (1.0, 0.0, -1.0), (6, 3, 1)),  # clamped at the grid's edge
    (CENTRE, (-0.5, 0.0, 0.0), (2, 3, 3)),     # -1 cell (0.5 x 2)
    (CENTRE, (0.2, -0.2, 0.2), (3, 3, 3)),     # rounds to no move
    (CENTRE, (0.0, 3.0, -7.0), (3, 5, 1)),     # clipped to [-1, 1]
])
def test_an_action_moves_up_to_max_move_cells_per_axis(start, action, expected):
    env = bowl_continuous(max_move=2)
    env.reset(seed=0, options={"start": start})
    _, _, _, _, info = env.step(np.array(action, dtype=np.float32))
    assert info["cell"] == flat(expected)


def test_reward_and_observation_are_the_discrete_envs():
    discrete = HandoverEnv(LandscapeScores(bowl_landscape()), observation="position")
    env = bowl_continuous()
    env.reset(seed=0, options={"start": (0, 0, 0)})
    obs, reward, terminated, truncated, info = env.step(np.array([1, 1, 1], dtype=np.float32))
    cell = flat((5, 5, 5))
    assert info["cell"] == cell and reward == discrete.reward(cell)
    np.testing.assert_array_equal(obs, discrete.observe(cell))
    assert not terminated and not truncated


def test_bad_arguments_are_refused_in_one_line():
    with pytest.raises(ConfigError, match="max_move = 0 is outside the valid range"):
        bowl_continuous(max_move=0)
    with pytest.raises(ConfigError, match="observation = 'indices' is not allowed"):
        bowl_continuous(observation="indices")
    env = bowl_continuous()
    env.reset(seed=0)
    with pytest.raises(ConfigError, match="is not 3 finite numbers"):
        env.step(np.array([0.0, np.nan, 0.0]))


@pytest.mark.slow
def test_the_sac_agent_gets_the_continuous_env():
    scores = LandscapeScores(bowl_landscape())
    env = make("sac", scores.grid, 0).env(scores)
    assert isinstance(env, ContinuousHandoverEnv)
    with pytest.raises(ConfigError, match="SAC needs the continuous-action env"):
        run_sac(HandoverEnv(LandscapeScores(bowl_landscape()), observation="position"),
                Budget(steps=10), 0)


@pytest.mark.slow
def test_a_short_sac_run_keeps_its_caps_and_is_deterministic():
    config = SACConfig(learning_starts=20)
    a, b = (run_sac(bowl_continuous(episode_end="none"), Budget(steps=60), 1, config)
            for _ in range(2))
    assert a.steps == 60 and a.stopped_by == "step_cap" and a.model is not None
    pd.testing.assert_frame_equal(a.trace.drop(columns="time_s"),
                                  b.trace.drop(columns="time_s"))


@pytest.mark.slow
def test_sac_runs_through_the_protocol_and_train(tmp_path):
    scores = LandscapeScores(bowl_landscape())
    result = run(make("sac", scores.grid, 0), scores, Budget(steps=50))
    assert result.steps == 50 and result.searcher == "sac"
    assert result.settings == dataclasses.asdict(SACConfig())
    bowl = bowl_landscape().save(tmp_path / "bowl.npz")
    out = tmp_path / "sac"
    assert main(["train", "--agent", "sac", "--steps", "50", "--landscape", str(bowl),
                 "--output", str(out)]) == 0
    assert pd.read_csv(out / "trace.csv")["step"].iloc[-1] == 50
