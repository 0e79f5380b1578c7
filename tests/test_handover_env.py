"""HandoverEnv: actions, rewards, infeasibility, episode ends, seeding, the checkers, and score
sources (landscape and online evaluate() give the same numbers)."""

from __future__ import annotations

import math
import subprocess
import sys

import gymnasium
import numpy as np
import pytest
from synthetic import CENTRE, INFEASIBLE, bowl_env, bowl_landscape, flat

from ergohandover.envs import (
    ENV_ID,
    EPISODE_STEPS,
    HandoverEnv,
    LandscapeScores,
    OnlineScores,
    register,
)
from ergohandover.envs.handover_env import INFEASIBLE_REWARD, symmetry_term
from ergohandover.landscape import landscape_of
from ergohandover.landscape.grid import Grid
from ergohandover.twin.evaluate import Evaluator
from ergohandover.twin.task import Boundary


@pytest.mark.parametrize("observation", ["indices", "position"])
def test_the_env_passes_gymnasiums_and_sb3s_checkers(observation):
    from gymnasium.utils.env_checker import check_env
    from stable_baselines3.common.env_checker import check_env as sb3_check_env

    check_env(bowl_env(observation=observation), skip_render_check=True)
    sb3_check_env(bowl_env(observation=observation), warn=True)


@pytest.mark.parametrize(("action", "delta"), [(0, (1, 0, 0)), (1, (-1, 0, 0)), (2, (0, 1, 0)),
                                               (3, (0, -1, 0)), (4, (0, 0, 1)), (5, (0, 0, -1))])
def test_actions_move_one_cell_in_the_papers_order(action, delta):
    env = bowl_env()
    obs, _ = env.reset(options={"start": (2, 3, 4)})
    obs, *_, info = env.step(action)
    expected = np.add((2, 3, 4), delta)
    np.testing.assert_array_equal(obs, expected)
    assert info["cell"] == flat(tuple(expected))
    np.testing.assert_allclose(info["location"], env.grid.coordinates([info["cell"]])[0])


def test_moves_off_the_grid_are_clamped():
    env = bowl_env()
    corner = {0: (6, 2, 2), 1: (0, 2, 2), 2: (2, 6, 2), 3: (2, 0, 2), 4: (2, 2, 6), 5: (2, 2, 0)}
    for action, start in corner.items():
        env.reset(options={"start": start})
        obs, *_ = env.step(action)
        np.testing.assert_array_equal(obs, start)


def test_the_reward_is_inverse_square_score_plus_the_codes_symmetry_term():
    assert symmetry_term(0.0) == pytest.approx(-0.5 * 0.001 ** 2)
    assert symmetry_term(-0.1) == symmetry_term(0.1) == pytest.approx(-0.5 * 0.199 ** 2)
    env = bowl_env()
    env.reset(options={"start": (3, 3, 3)})
    _, reward, _, _, info = env.step(0)  # to (4, 3, 3): distance 1 -> score 6, x = 0.03 m
    assert info["score"] == 6
    assert reward == pytest.approx(1 / 36 - 0.5 * (0.06 - 0.001) ** 2)
    assert env.reward(flat((4, 3, 3))) == reward


def test_an_infeasible_cell_gives_minus_one_and_the_box_stays_there():
    env = bowl_env(observation="position")
    env.reset(options={"start": (5, 6, 6)})
    obs, reward, terminated, truncated, info = env.step(0)
    assert reward == INFEASIBLE_REWARD == -1.0
    assert info["score"] == math.inf and info["cell"] == flat(INFEASIBLE)
    assert obs[3] == 1.0 and not terminated and not truncated
    np.testing.assert_allclose(obs[:3], 1.0)
    obs, reward, *_ = env.step(1)  # and it can walk back out
    # (5, 6, 6) is sqrt(22) = 4.7 cells from the centre: score 10 of paper_postural's 14
    assert reward > 0 and obs[3] == pytest.approx(10 / 14)


def test_episode_end_paper_terminates_at_the_target_and_none_never():
    env = bowl_env(target=5)
    env.reset(options={"start": (2, 3, 3)})
    *_, terminated, truncated, info = env.step(0)
    assert terminated and not truncated and info["score"] == 5
    env = bowl_env()  # the paper's target 4 is below this landscape's minimum
    env.reset(options={"start": (2, 3, 3)})
    assert not env.step(0)[2]
    env = bowl_env(episode_end="none", target=5)
    env.reset(options={"start": (2, 3, 3)})
    assert not env.step(0)[2]


def test_reset_is_seeded_uniform_and_can_be_fixed():
    env = bowl_env()
    starts = [env.reset(seed=s)[1]["cell"] for s in (3, 4, 3)]
    assert starts[0] == starts[2] != starts[1]
    counts = np.bincount([env.reset()[1]["cell"] for _ in range(34_300)], minlength=343)
    assert counts.min() > 60 and counts.max() < 145  # 100 expected per cell
    assert bowl_env(start=(1, 2, 3)).reset(seed=9)[1]["cell"] == flat((1, 2, 3))
    assert bowl_env(start=17).reset()[1]["cell"] == 17
    with pytest.raises(ValueError, match="start = 343 is outside the valid range 0-342"):
        bowl_env(start=343)


def test_register_is_idempotent_and_make_truncates_episodes():
    assert register() == register() == ENV_ID
    env = gymnasium.make(ENV_ID, scores=LandscapeScores(bowl_landscape()), start=(0, 0, 0))
    assert env.spec.max_episode_steps == EPISODE_STEPS
    env = gymnasium.make(ENV_ID, scores=LandscapeScores(bowl_landscape()), start=(0, 0, 0),
                         max_episode_steps=3)
    env.reset(seed=0)
    ends = [env.step(1)[2:4] for _ in range(3)]
    assert ends == [(False, False), (False, False), (False, True)]


def test_bad_options_are_rejected_with_the_allowed_values():
    with pytest.raises(ValueError, match="observation = 'pixels' is not allowed"):
        bowl_env(observation="pixels")
    with pytest.raises(ValueError, match="episode_end = 'never' is not allowed"):
        bowl_env(episode_end="never")
    with pytest.raises(ValueError, match="objective = 'owas' is not allowed"):
        HandoverEnv(landscape=bowl_landscape(), objective="owas")
    env = bowl_env()
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action = 6 is outside the valid range 0-5"):
        env.step(6)


def test_a_landscape_file_builds_the_env(tmp_path):
    bowl_landscape().save(tmp_path / "bowl.npz")
    env = HandoverEnv(landscape=tmp_path / "bowl.npz", objective="rula", start=CENTRE)
    assert env.reset()[1]["score"] == 5.0 and env.objective == "rula"


def test_importing_and_stepping_the_env_does_not_load_torch():
    code = ("import sys; from ergohandover.envs import HandoverEnv, LandscapeScores; "
            "from test_handover_env import bowl_landscape; "
            "env = HandoverEnv(LandscapeScores(bowl_landscape())); env.reset(seed=0); "
            "env.step(0); print('torch' in sys.modules, 'stable_baselines3' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=__file__.rsplit("/", 1)[0], check=True).stdout
    assert out.split() == ["False", "False"]


SMALL = Boundary((-0.10, 0.10), (0.90, 1.20), (0.15, 0.75))  # 5 x 7 x 13, 17% infeasible


@pytest.fixture(scope="module")
def small_landscape():
    return landscape_of(Evaluator(), Grid(SMALL, 0.05), progress=False)


@pytest.mark.parametrize("objective", ["paper_postural", "reba", "reba_ab", "rula"])
def test_online_scores_equal_the_landscapes(small_landscape, objective):
    stored = LandscapeScores(small_landscape, objective)
    online = OnlineScores(small_landscape.grid, Evaluator(), objective, block=3)
    cells = np.random.default_rng(0).permutation(small_landscape.grid.size).tolist()
    assert [online.score(c) for c in cells] == [stored.score(c) for c in cells]
    assert math.inf in [stored.score(c) for c in cells]  # the grid has infeasible points
    assert online.evaluations <= 2 * small_landscape.grid.size  # blocks, not one call per cell


def test_online_and_landscape_envs_walk_identically(small_landscape):
    runs = []
    for scores in (LandscapeScores(small_landscape),
                   OnlineScores(small_landscape.grid, Evaluator())):
        env = HandoverEnv(scores)
        env.reset(seed=5)
        runs.append([env.step(a)[1:] for a in np.random.default_rng(1).integers(6, size=60)])
    assert runs[0] == runs[1]


def test_importing_the_env_package_registers_the_env(tmp_path):
    """As Gymnasium environment packages do: ``import ergohandover.envs`` is enough."""
    path = tmp_path / "bowl.npz"
    bowl_landscape().save(path)
    code = ("import gymnasium, ergohandover.envs\n"
            f"env = gymnasium.make('ergohandover/Handover-v0', landscape={str(path)!r})\n"
            "obs, info = env.reset(seed=0)\n"
            "print(env.spec.max_episode_steps, info['score'] >= 5)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split()
    assert out == [str(EPISODE_STEPS), "True"]
