"""normalize_observations: a model trained with it predicts in Python as ``rdsim replay`` acts (the
transform is part of the model file)."""
import json
import re
import subprocess

import numpy as np

import rdsim
from conftest import ROOT, rdsim_binary


def test_predict_of_a_normalised_model_is_replay(tmp_path):
    config = json.loads((ROOT / "configs" / "jaka_button.json").read_text())
    config.update(normalize_observations=True, total_timesteps=8192, seed=3)
    config.pop("eval", None)
    rdsim.train(config, log_dir=str(tmp_path / "run"), quiet=True)
    model_path = tmp_path / "run" / "model.bin"
    model = rdsim.load_model(model_path)
    assert model.config["normalize_observations"] is True

    replay = subprocess.run([str(rdsim_binary()), "replay", str(model_path), "--episodes", "3"],
                            check=True, capture_output=True, text=True, timeout=120).stdout
    expected = [float(x) for x in re.findall(r"episode \d+: return (-?[\d.]+)", replay)]
    assert len(expected) == 3

    # The same episodes in Python: the env of the model's config, the first reset seeded as replay's.
    options = {k: v for k, v in model.config["env"].items() if k != "name"}
    env = rdsim.make("rdsim/JakaButton-v0", **options)
    returns = []
    obs, _ = env.reset(seed=model.config["seed"])
    for _ in range(3):
        total, done = 0.0, False
        while not done:
            obs, reward, terminated, truncated, _ = env.step(model.predict(obs))
            total += reward
            done = terminated or truncated
        returns.append(total)
        obs, _ = env.reset()
    env.close()
    np.testing.assert_allclose(returns, expected, atol=0.006)  # replay prints two decimals
