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
