"""Domain randomization from Python: the env's "randomize" option through rdsim.make and make_vec
(the same noise and draws for the same seed), the queued actions in a goal env's observation through
Gymnasium's checker, and a bad value as one rdsim.Error naming the key."""
import numpy as np
import pytest

import rdsim


def test_randomize_through_make_and_make_vec_follows_the_seed():
    options = {"randomize": {"observation_noise": 0.01, "action_latency": 1}}
    a = rdsim.make("rdsim/JakaButton-v0", **options)
    b = rdsim.make("rdsim/JakaButton-v0", **options)
    plain = rdsim.make("rdsim/JakaButton-v0")
    oa, _ = a.reset(seed=3)
    ob, _ = b.reset(seed=3)
    op, _ = plain.reset(seed=3)
    np.testing.assert_array_equal(oa, ob)
    assert not np.array_equal(oa, op)
    assert np.abs(oa - op).max() < 0.1
    assert a.config["randomize"]["observation_noise"] == 0.01
    assert a.config["randomize"]["action_latency"] == 1
    assert a.config["randomize"]["mass_scale"] == [1.0, 1.0]  # every key, with its default
    venv = rdsim.make_vec("rdsim/JakaButton-v0", 2, **options)
    first, _ = venv.reset(seed=4)
    again, _ = venv.reset(seed=4)
    np.testing.assert_array_equal(first, again)
    for env in (a, b, plain, venv):
        env.close()


def test_a_bad_randomize_value_is_one_error_naming_the_key():
    with pytest.raises(rdsim.Error, match=r"randomize\.action_latency: 10 steps is not shorter"):
        rdsim.make("rdsim/JakaButton-v0", max_steps=10, randomize={"action_latency": 10})
    with pytest.raises(rdsim.Error, match=r"randomize\.friction: unknown key"):
        rdsim.make("rdsim/JakaButton-v0", randomize={"friction": 0.5})


def test_per_episode_draws_and_the_queued_actions_pass_gymnasiums_checker():
    from gymnasium.utils.env_checker import check_env

    options = {"randomize": {"mass_scale": [0.7, 1.3], "friction_scale": [0.5, 1.5], "placement_noise": 0.01,
                             "action_latency": 1, "observe_latency": True}}
    env = rdsim.make("rdsim/JakaPush-v0", **options)
    plain = rdsim.make("rdsim/JakaPush-v0")
    check_env(env, skip_render_check=True)
    assert env.observation_space["observation"].shape[0] == plain.observation_space["observation"].shape[0] + 3
    obs, _ = env.reset(seed=2)
    again, _ = rdsim.make("rdsim/JakaPush-v0", **options).reset(seed=2)
    for key in obs:
        np.testing.assert_array_equal(obs[key], again[key])
    action = np.array([0.5, -0.2, 0.1], dtype=np.float32)
    obs, reward, *_ = env.step(action)
    np.testing.assert_array_equal(obs["observation"][-3:], action)
    assert reward == env.unwrapped.compute_reward(obs["achieved_goal"], obs["desired_goal"], {})
    env.close()
    plain.close()


def test_view_draws_need_raw_pixels():
    with pytest.raises(rdsim.Error, match=r"randomize\.camera_shift: applies to raw-pixel observations only"):
        rdsim.make("rdsim/JakaButton-v0", randomize={"camera_shift": 0.03})
    env = rdsim.make("rdsim/JakaButton-v0", observation="raw_pixels", randomize={"camera_shift": 0.03, "colour_noise": 0.1})
    plain = rdsim.make("rdsim/JakaButton-v0", observation="raw_pixels")
    assert not np.array_equal(env.reset(seed=1)[0], plain.reset(seed=1)[0])
    env.close()
    plain.close()


def test_observation_parts_name_the_values_and_take_their_own_noise():
    env = rdsim.make("rdsim/JakaPush-v0", randomize={"observation_noise_parts": {"cube1_position": 0.01}})
    plain = rdsim.make("rdsim/JakaPush-v0")
    parts = env.unwrapped.observation_parts
    assert list(parts)[:3] == ["effector_position", "effector_velocity", "cube1_position"]
    assert list(parts)[-2:] == ["achieved_goal", "desired_goal"]
    assert parts["desired_goal"] == slice(25, 28)
    obs, _ = env.reset(seed=5)
    clean, _ = plain.reset(seed=5)
    cube = parts["cube1_position"]
    moved = obs["observation"] - clean["observation"]
    assert np.abs(moved[cube]).max() > 0
    moved[cube] = 0
    np.testing.assert_array_equal(moved, 0)  # only the named part is noisy
    np.testing.assert_array_equal(obs["desired_goal"], clean["desired_goal"])
    venv = rdsim.make_vec("rdsim/JakaButton-v0", 2)
    assert venv.observation_parts == {"target_from_effector": slice(0, 3), "effector_position": slice(3, 6)}
    assert rdsim.make("rdsim/JakaButton-v0", observation="raw_pixels").unwrapped.observation_parts == {}
    with pytest.raises(rdsim.Error, match=r'observation_noise_parts: "cube_position" is not a part .*did you mean "cube1_position"'):
        rdsim.make("rdsim/JakaPush-v0", randomize={"observation_noise_parts": {"cube_position": 0.01}})
    for e in (env, plain, venv):
        e.close()
