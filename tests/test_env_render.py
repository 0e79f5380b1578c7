"""HandoverEnv's render modes: ``rgb_array`` pictures the worker holding the box at the env's
cell (the same picture for the same cell, another for another cell), ``human`` needs a display
and says so in one line, and any other mode is refused as Gymnasium envs refuse it."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic import CENTRE, bowl_env

from ergohandover.envs.handover_env import RENDER_MODES, RENDER_SIZE
from ergohandover.errors import ConfigError, UsageError

SKY = (255, 255, 255)
"""What TinyRenderer clears the picture to: the background above the floor."""


@pytest.fixture(scope="module")
def env():
    env = bowl_env(render_mode="rgb_array", start=CENTRE)
    yield env
    env.close()


def frame_at(env, cell) -> np.ndarray:
    env.reset(options={"start": cell})
    return env.render()


def coloured_share(image: np.ndarray) -> float:
    """The share of pixels in a clear colour: the worker's shirt and skin and the box (the sky
    is white, the floor and the robot grey)."""
    spread = image.max(axis=2).astype(int) - image.min(axis=2).astype(int)
    return float((spread > 40).mean())


def test_rgb_array_is_an_image_of_the_env_size(env):
    image = frame_at(env, CENTRE)
    width, height = RENDER_SIZE
    assert image.shape == (height, width, 3) and image.dtype == np.uint8


def test_the_image_shows_the_worker_and_the_box(env):
    image = frame_at(env, CENTRE)
    sky = (image == SKY).all(axis=2).mean()
    assert 0.2 < sky < 0.9  # the scene stands in front of the sky, not instead of it
    assert coloured_share(image) > 0.03


def test_the_image_follows_the_cell_and_is_the_same_for_the_same_cell(env):
    first = frame_at(env, CENTRE)
    env.step(2)  # +y: the box one cell up, the worker's arms with it
    moved = env.render()
    lowest = frame_at(env, (3, 0, 3))
    again = frame_at(env, CENTRE)
    assert not np.array_equal(first, moved) and not np.array_equal(first, lowest)
    assert np.array_equal(first, again)


def test_render_before_reset_is_a_usage_error():
    env = bowl_env(render_mode="rgb_array")
    with pytest.raises(UsageError, match=r"call reset\(\) before render\(\)"):
        env.render()
    env.close()


# Made directly, the env has no spec, so the checker cannot make it in its other modes (and
# "human" would need a display): it says so, which is not what this test is about.
@pytest.mark.filterwarnings("ignore:.*not having a spec")
def test_the_env_passes_gymnasiums_checker_with_rgb_array():
    from gymnasium.utils.env_checker import check_env

    env = bowl_env(render_mode="rgb_array")
    check_env(env)
    env.close()
    env.close()  # closing twice is harmless


def test_human_without_a_display_is_one_line_naming_the_mode(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    with pytest.raises(ConfigError) as caught:
        bowl_env(render_mode="human")
    message = str(caught.value)
    assert "\n" not in message
    assert message.startswith("render_mode = 'human' needs a display")
    assert "DISPLAY" in message and "ergohandover view" in message


def test_an_unknown_render_mode_is_refused_with_the_allowed_ones():
    with pytest.raises(ValueError, match="render_mode = 'ansi' is not allowed") as caught:
        bowl_env(render_mode="ansi")
    assert all(mode in str(caught.value) for mode in RENDER_MODES)


def test_the_metadata_declares_the_modes_and_a_frame_rate():
    env = bowl_env()
    assert list(env.metadata["render_modes"]) == list(RENDER_MODES)
    assert env.metadata["render_fps"] > 0
    assert env.render_mode is None
    with pytest.warns(UserWarning, match="without a render_mode"):
        assert env.render() is None
