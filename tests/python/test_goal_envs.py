"""The goal-conditioned manipulation tasks from Python: Gymnasium-Robotics' GoalEnv layout (Dict
observations, compute_reward, is_success) through make and make_vec, and Stable-Baselines3's SAC with
its HerReplayBuffer on rdsim/JakaPush-v0 through make_vec."""
import gymnasium
import numpy as np
import pytest

import rdsim

GOAL_IDS = ["rdsim/JakaReachGoal-v0", "rdsim/JakaPush-v0", "rdsim/JakaPickAndPlace-v0", "rdsim/JakaStack-v0"]
KEYS = {"observation", "achieved_goal", "desired_goal"}


@pytest.mark.parametrize("env_id", GOAL_IDS)
def test_dict_observations_and_compute_reward_match_step(env_id):
    env = rdsim.make(env_id)
    assert isinstance(env.observation_space, gymnasium.spaces.Dict) and set(env.observation_space.spaces) == KEYS
    obs, _ = env.reset(seed=3)
    assert env.observation_space.contains(obs)
    env.action_space.seed(3)
    achieved, desired, rewards = [], [], []
    for _ in range(20):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert info["is_success"] == info["success"] and isinstance(reward, float)
        assert env.compute_reward(obs["achieved_goal"], obs["desired_goal"], info) == reward
        achieved.append(obs["achieved_goal"])
        desired.append(obs["desired_goal"])
        rewards.append(reward)
        if terminated or truncated:
            break
    batch = env.compute_reward(np.stack(achieved), np.stack(desired), None)
    assert batch.dtype == np.float32 and batch.shape == (len(rewards),)
    np.testing.assert_array_equal(batch, np.asarray(rewards, dtype=np.float32))
    # Relabelled: the achieved goal as the desired one is a success.
    assert env.compute_reward(obs["achieved_goal"], obs["achieved_goal"], None) == 0.0
    env.close()


def test_dense_reward_is_minus_the_distance():
    env = rdsim.make("rdsim/JakaPush-v0", reward_type="dense")
    a, d = np.array([0.1, 0.2, 0.02], np.float32), np.array([0.1, 0.5, 0.06], np.float32)
    assert env.compute_reward(a, d, None) == pytest.approx(-np.linalg.norm(a - d), rel=1e-6)
    env.close()


def test_partial_reward_pays_each_cube_on_its_goal():
    env = rdsim.make("rdsim/JakaStack-v0", reward_type="partial")
    d = np.array([0.4, 0.0, 0.02, 0.4, 0.0, 0.06], np.float32)
    one = d + np.array([0.01, 0, 0, 0.2, 0, 0], np.float32)  # the first cube placed, the second far
    np.testing.assert_array_equal(env.compute_reward(np.stack([d, one, d + 0.3]), np.stack([d, d, d]), None),
                                  np.array([0.0, -0.5, -1.0], np.float32))
    env.close()


def test_non_goal_envs_have_no_compute_reward():
    env = rdsim.make("rdsim/JakaButton-v0")
    assert not hasattr(env, "compute_reward") and env.goal is None
    env.close()


def test_make_vec_gives_batched_dicts_and_final_observations():
    venv = rdsim.make_vec("rdsim/JakaPush-v0", 3, num_threads=2, max_steps=4)
    assert isinstance(venv.single_observation_space, gymnasium.spaces.Dict)
    obs, _ = venv.reset(seed=5)
    assert set(obs) == KEYS and obs["desired_goal"].shape == (3, 3)
    assert venv.observation_space.contains(obs)
    for _ in range(4):
        obs, reward, terminated, truncated, info = venv.step(np.zeros((3, 3), np.float32))
    assert (terminated | truncated).all()
    final = info["final_obs"][0]
    assert set(final) == KEYS
    np.testing.assert_array_equal(
        venv.compute_reward(np.stack([info["final_obs"][i]["achieved_goal"] for i in range(3)]),
                            np.stack([info["final_obs"][i]["desired_goal"] for i in range(3)]), None),
        reward)
    venv.close()


def learn_300_steps_with_her(algorithm: str, env_id: str, **options) -> None:
    """SB3's `algorithm` ("SAC", "DQN") + HerReplayBuffer for 300 steps on 2 envs of rdsim.make_vec."""
    torch = pytest.importorskip("torch")
    import stable_baselines3
    from stable_baselines3 import HerReplayBuffer
    from stable_baselines3.common.vec_env import VecMonitor

    from rdsim.sb3 import SB3VecEnv

    torch.set_num_threads(1)
    venv = VecMonitor(SB3VecEnv(rdsim.make_vec(env_id, 2, num_threads=1, seed=0, **options)))
    model = getattr(stable_baselines3, algorithm)(
        "MultiInputPolicy", venv, replay_buffer_class=HerReplayBuffer,
        replay_buffer_kwargs={"n_sampled_goal": 4, "goal_selection_strategy": "future"},
        learning_starts=100, batch_size=64, policy_kwargs={"net_arch": [32, 32]}, seed=0, verbose=0)
    model.learn(total_timesteps=300)
    assert model.replay_buffer.size() > 0 and model.num_timesteps >= 300
    venv.close()


def test_sb3_sac_with_her_trains_on_jaka_push_through_make_vec():
    learn_300_steps_with_her("SAC", "rdsim/JakaPush-v0")


def test_discrete_moves_of_reach_goal_and_push_train_sb3_dqn_with_her():
    """is_discrete: Discrete(6) effector moves, the Box move of one unit along an axis; SB3's DQN +
    HerReplayBuffer trains on them through make_vec."""
    for env_id in ("rdsim/JakaReachGoal-v0", "rdsim/JakaPush-v0"):
        discrete, box = rdsim.make(env_id, is_discrete=True), rdsim.make(env_id)
        assert discrete.action_space == gymnasium.spaces.Discrete(6)
        a, _ = discrete.reset(seed=5)
        b, _ = box.reset(seed=5)
        a, *_ = discrete.step(3)  # +y
        b, *_ = box.step(np.array([0.0, 1.0, 0.0], dtype=np.float32))
        for key in a:
            np.testing.assert_array_equal(a[key], b[key])
        discrete.close()
        box.close()
    learn_300_steps_with_her("DQN", "rdsim/JakaReachGoal-v0", is_discrete=True)


def test_joint_control_moves_the_arms_joints_and_observes_them():
    env = rdsim.make("rdsim/JakaPickAndPlace-v0", control="joints")
    assert env.action_space.shape == (7,)  # six arm joints, then the fingers
    parts = env.unwrapped.observation_parts
    assert parts["joint_positions"] == slice(7, 13)
    obs, _ = env.reset(seed=2)
    before = obs["observation"][parts["joint_positions"]].copy()
    action = np.zeros(7, np.float32)
    action[0] = 0.5  # the base joint's target 0.1 rad further
    for _ in range(3):
        obs, *_ = env.step(action)
    moved = obs["observation"][parts["joint_positions"]] - before
    assert moved[0] > 0.1 and np.abs(moved[1:]).max() < 0.02
    env.close()


PIXELS = {"observation": "raw_pixels", "image_width": 40, "image_height": 32}


@pytest.mark.parametrize("channels", ["rgb", "depth"])
def test_raw_pixels_observe_the_image_with_the_goals_beside_it(channels):
    env = rdsim.make("rdsim/JakaPush-v0", image_channels=channels, **PIXELS)
    truth = rdsim.make("rdsim/JakaPush-v0")
    space = env.observation_space
    assert isinstance(space, gymnasium.spaces.Dict) and set(space.spaces) == KEYS
    image = space["observation"]
    assert image.shape == ((32, 40, 3) if channels == "rgb" else (32, 40, 1))
    assert image.dtype == (np.uint8 if channels == "rgb" else np.float32)
    assert space["achieved_goal"].shape == space["desired_goal"].shape == (3,)
    obs, _ = env.reset(seed=4)
    want, _ = truth.reset(seed=4)
    assert space.contains(obs)
    for _ in range(12):  # the same physics as ground truth: the same goals and rewards
        np.testing.assert_array_equal(obs["achieved_goal"], want["achieved_goal"])
        np.testing.assert_array_equal(obs["desired_goal"], want["desired_goal"])
        action = np.array([0.5, -0.3, -1.0], np.float32)
        obs, reward, *_ = env.step(action)
        want, want_reward, *_ = truth.step(action)
        assert reward == want_reward == env.compute_reward(obs["achieved_goal"], obs["desired_goal"], None)
    if channels == "rgb":
        assert obs["observation"].max() > obs["observation"].min()
    env.close()
    truth.close()


def test_raw_pixels_through_make_vec_in_worker_processes():
    venv = rdsim.make_vec("rdsim/JakaPush-v0", 3, num_threads=2, seed=5, max_steps=4, **PIXELS)
    assert venv.uses_processes  # osmesa pixels: processes by default
    single = rdsim.make("rdsim/JakaPush-v0", max_steps=4, **PIXELS)
    obs, _ = venv.reset(seed=5)
    assert set(obs) == KEYS and obs["observation"].shape == (3, 32, 40, 3) and obs["desired_goal"].shape == (3, 3)
    assert venv.observation_space.contains(obs)
    first, _ = single.reset(seed=int(rdsim._rdsim.env_seed(5, 1)))
    np.testing.assert_array_equal(obs["observation"][1], first["observation"])
    np.testing.assert_array_equal(obs["desired_goal"][1], first["desired_goal"])
    for _ in range(4):
        obs, reward, terminated, truncated, info = venv.step(np.zeros((3, 3), np.float32))
        mine, own_reward, *_ = single.step(np.zeros(3, np.float32))
    assert (terminated | truncated).all()
    final = info["final_obs"][1]
    assert set(final) == KEYS and final["observation"].dtype == np.uint8
    np.testing.assert_array_equal(final["observation"], mine["observation"])
    np.testing.assert_array_equal(final["achieved_goal"], mine["achieved_goal"])
    assert reward[1] == own_reward
    venv.close()
    single.close()


def test_raw_pixels_train_with_sb3_multi_input_policy_and_her():
    torch = pytest.importorskip("torch")
    from stable_baselines3 import SAC, HerReplayBuffer
    from stable_baselines3.common.env_checker import check_env

    torch.set_num_threads(1)
    env = rdsim.make("rdsim/JakaPush-v0", observation="raw_pixels", image_width=48, image_height=48)  # NatureCNN's least: 36
    check_env(env)
    model = SAC("MultiInputPolicy", env, replay_buffer_class=HerReplayBuffer, buffer_size=1000, learning_starts=60,
                batch_size=16, policy_kwargs={"net_arch": [16], "normalize_images": True}, seed=0, verbose=0)
    model.learn(total_timesteps=80)
    assert model.replay_buffer.size() > 0 and model.num_timesteps >= 80
    env.close()


def test_rdsims_own_training_refuses_pixel_goal_envs_clearly(tmp_path):
    with pytest.raises(rdsim.Error, match="raw_pixels.*goal env.*ground_truth"):
        rdsim.train({"algorithm": "sac", "env": {"name": "push", **PIXELS}, "total_timesteps": 1000},
                    log_dir=tmp_path / "run", quiet=True)
