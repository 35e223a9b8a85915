"""Gymnasium's and Stable-Baselines3's own env checkers, unmodified, on every env: no warnings."""
import warnings

import gymnasium
import pytest
from gymnasium.utils.env_checker import check_env as gymnasium_check_env

import rdsim
from cases import advice_only, case_name, env_cases

CASES = env_cases()


@pytest.mark.parametrize("case", CASES, ids=[case_name(c) for c in CASES])
def test_gymnasium_check_env(case):
    env_id, options = case
    env = rdsim.make(env_id, **options)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        gymnasium_check_env(env)
    assert [str(w.message) for w in advice_only(env_id, caught)] == []
    env.close()


@pytest.mark.parametrize("case", CASES, ids=[case_name(c) for c in CASES])
def test_sb3_check_env(case):
    from stable_baselines3.common.env_checker import check_env as sb3_check_env

    env_id, options = case
    env = rdsim.make(env_id, **options)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sb3_check_env(env, warn=True)
    assert [str(w.message) for w in advice_only(env_id, caught)] == []
    env.close()


def test_gymnasium_make_registered_ids():
    for env in rdsim.envs():
        e = gymnasium.make(env["id"])
        obs, info = e.reset(seed=1)
        assert e.observation_space.contains(obs)
        e.close()
    # The module-import form needs no import of rdsim first.
    assert gymnasium.make("rdsim:rdsim/JakaButton-v0").unwrapped.config["name"] == "jaka_button"


def test_spaces_are_exact():
    env = rdsim.make("rdsim/JakaButton-v0")
    assert isinstance(env.action_space, gymnasium.spaces.Discrete) and env.action_space.n == 6
    assert env.observation_space.dtype.name == "float32"
    box = rdsim.make("rdsim/JakaButton-v0", is_discrete=False)
    assert isinstance(box.action_space, gymnasium.spaces.Box) and box.action_space.dtype.name == "float32"
    pix = rdsim.make("rdsim/JakaButton-v0", observation="raw_pixels", image_width=40, image_height=32)
    assert pix.observation_space.shape == (32, 40, 3) and pix.observation_space.dtype.name == "uint8"
    assert pix.observation_space.low.min() == 0 and pix.observation_space.high.max() == 255
    multi = rdsim.make("rdsim/JakaButton-v0", observation="raw_pixels", multi_view=True, image_width=36, image_height=36)
    assert multi.observation_space.shape == (36, 36, 6)


def test_depth_and_segmentation_channels_pass_the_checkers_single_and_vector():
    options = dict(observation="raw_pixels", image_channels="rgb_depth_segmentation", image_width=36, image_height=32)
    env = rdsim.make("rdsim/JakaButton-v0", **options)
    space = env.observation_space
    assert space.shape == (32, 36, 5) and space.dtype.name == "float32"
    assert (space.low == 0).all() and (space.high[..., :3] == 1).all() and (space.high[..., 4] == 255).all()
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        gymnasium_check_env(env)
    obs, _ = env.reset(seed=2)
    assert space.contains(obs)
    assert obs[..., 4].max() >= 3 and (obs[..., 4] == obs[..., 4].round()).all()  # integer ids, several bodies
    depth = rdsim.make("rdsim/JakaButton-v0", observation="raw_pixels", image_channels="depth", image_width=36,
                       image_height=32).reset(seed=2)[0]
    assert (depth[..., 0] == obs[..., 3]).all()
    vec = rdsim.make_vec("rdsim/JakaButton-v0", 2, **options)
    batch, _ = vec.reset(seed=2)
    assert batch.shape == (2, 32, 36, 5) and batch.dtype.name == "float32"
    assert vec.single_observation_space.contains(batch[1])
    vec.close()


def test_render_rgb_array():
    env = rdsim.make("rdsim/JakaButton-v0", render_mode="rgb_array", render_width=64, render_height=48)
    env.reset(seed=3)
    frame = env.render()
    assert frame.shape == (48, 64, 3) and frame.dtype.name == "uint8" and frame.std() > 0
    assert rdsim.make("rdsim/JakaButton-v0").render() is None


def test_info_keys_and_config():
    env = rdsim.make("rdsim/JakaObstacle-v0", max_steps=7)
    assert env.config["max_steps"] == 7 and env.config["name"] == "jaka_obstacle"
    env.reset(seed=0)
    for t in range(7):
        _, _, terminated, truncated, info = env.step(env.action_space.sample())
        assert set(info) == {"success", "collision", "out_of_bounds", "distance"}
        if terminated or truncated:
            break
    assert terminated or truncated
