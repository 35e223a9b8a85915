"""load_model: a policy trained by the rdsim binary, acting on batches of NumPy observations."""
import subprocess

import numpy as np
import pytest

import rdsim
from conftest import ROOT, rdsim_binary


@pytest.fixture(scope="module")
def model_path(tmp_path_factory):
    binary = rdsim_binary()
    if not binary.exists():
        pytest.fail(f"{binary} not found: build rdsim first (tools/setup.sh) or set RDSIM_BIN")
    run = tmp_path_factory.mktemp("run")
    subprocess.run([str(binary), "train", "--config", str(ROOT / "configs" / "cartpole_ppo.json"), "--timesteps", "2048", "-q",
                    "--log-dir", str(run)], check=True, capture_output=True, timeout=300)
    return run / "model.bin"


def test_predict_batches_and_config(model_path):
    model = rdsim.load_model(model_path)
    assert model.algorithm == "ppo" and model.config["env"]["name"] == "cartpole"
    venv = rdsim.make_vec("rdsim/CartPole-v1", 5)
    obs, _ = venv.reset(seed=0)
    actions = model.predict(obs)
    assert actions.shape == (5,) and actions.dtype == np.int64
    assert venv.action_space.contains(actions)
    np.testing.assert_array_equal(actions, model.predict(obs, deterministic=True))
    assert model.predict(obs[0]) == actions[0]
    venv.step(actions)
    venv.close()


def test_predict_bad_input_raises(model_path):
    model = rdsim.load_model(model_path)
    for bad in (np.zeros((2, 3), np.float32), np.zeros((2, 4), np.int64), np.full((1, 4), np.nan, np.float32), "x"):
        with pytest.raises(rdsim.Error):
            model.predict(bad)


def test_damaged_model_raises(model_path, tmp_path):
    data = bytearray(model_path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    damaged = tmp_path / "damaged.bin"
    damaged.write_bytes(bytes(data))
    with pytest.raises(rdsim.Error, match="damaged"):
        rdsim.load_model(damaged)


def test_a_goal_env_model_takes_the_dict_observations(tmp_path):
    """A goal env's model acts on what rdsim.make_vec returns (dicts) as on the flat vectors."""
    run = tmp_path / "run"
    subprocess.run([str(rdsim_binary()), "train", "--config", str(ROOT / "configs" / "jaka_reach_goal_dqn.json"),
                    "--timesteps", "1200", "-q", "--log-dir", str(run)], check=True, capture_output=True, timeout=300)
    model = rdsim.load_model(run / "model.bin")
    venv = rdsim.make_vec("rdsim/JakaReachGoal-v0", 3, is_discrete=True)
    obs, _ = venv.reset(seed=1)
    flat = np.concatenate([obs["observation"], obs["achieved_goal"], obs["desired_goal"]], axis=-1)
    actions = model.predict(obs)
    assert actions.shape == (3,) and venv.action_space.contains(actions)
    np.testing.assert_array_equal(actions, model.predict(flat))
    assert model.predict({key: value[0] for key, value in obs.items()}) == actions[0]
    venv.close()
    with pytest.raises(rdsim.Error, match="expected a dict of observation, achieved_goal, desired_goal"):
        model.predict({"observation": obs["observation"]})
    with pytest.raises(rdsim.Error, match="desired_goal of shape"):
        model.predict({**obs, "desired_goal": obs["desired_goal"][:, :2]})


def test_a_dict_for_a_model_without_goals_raises(model_path):
    with pytest.raises(rdsim.Error, match="a dict of observations is for goal envs"):
        rdsim.load_model(model_path).predict({"observation": np.zeros((1, 4), np.float32)})
