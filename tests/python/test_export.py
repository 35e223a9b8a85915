"""rdsim export / Model.export_onnx: the ONNX model of every exportable policy kind gives rdsim's own
actions in onnxruntime (issue #43: max |difference| <= 1e-5 for Box actions, identical discrete
actions, on 1,000 observations), and passes onnx.checker."""
import subprocess

import gymnasium
import numpy as np
import onnx
import onnxruntime
import pytest

import rdsim
from conftest import rdsim_binary

# (name, config): one short run of each policy kind: discrete and Gaussian actor-critics, the
# squashed Gaussian (SAC), deterministic actors (TD3, DDPG), Q-networks (DQN), with and without
# observation normalisation, a shared trunk and an input scale.
SMALL = {"hidden_sizes": [32, 32]}
CASES = [
    ("ppo_discrete", {"algorithm": "ppo", "env": {"name": "jaka_button", "is_discrete": True}, "num_envs": 4,
                      "total_timesteps": 2048, "network": SMALL, "ppo": {"n_steps": 128, "batch_size": 128}}),
    ("ppo_box_normalized", {"algorithm": "ppo", "env": {"name": "pendulum"}, "num_envs": 4, "total_timesteps": 2048,
                            "normalize_observations": True, "network": SMALL,
                            "ppo": {"n_steps": 128, "batch_size": 128}}),
    ("a2c_shared_trunk", {"algorithm": "a2c", "env": {"name": "cartpole"}, "num_envs": 4, "total_timesteps": 2000,
                          "network": {"hidden_sizes": [32, 32], "shared": True}}),
    ("trpo_scaled", {"algorithm": "trpo", "env": {"name": "pendulum"}, "num_envs": 2, "total_timesteps": 2048,
                     "network": {"hidden_sizes": [32, 32], "input_scale": 0.5}, "trpo": {"n_steps": 512}}),
    ("dqn", {"algorithm": "dqn", "env": {"name": "cartpole"}, "total_timesteps": 1500, "network": SMALL,
             "dqn": {"learning_starts": 500}}),
    ("sac_normalized", {"algorithm": "sac", "env": {"name": "pendulum"}, "total_timesteps": 1200,
                        "normalize_observations": True, "network": SMALL,
                        "sac": {"learning_starts": 500, "batch_size": 64}}),
    ("td3", {"algorithm": "td3", "env": {"name": "pendulum"}, "total_timesteps": 1200, "network": SMALL,
             "td3": {"learning_starts": 500, "batch_size": 64}}),
    ("ddpg", {"algorithm": "ddpg", "env": {"name": "pendulum"}, "total_timesteps": 1200, "network": SMALL,
              "ddpg": {"learning_starts": 500, "batch_size": 64}}),
    ("ars_normalized", {"algorithm": "ars", "env": {"name": "cartpole"}, "total_timesteps": 3000,
                        "ars": {"n_delta": 4, "n_top": 2}}),
    ("cma_es_box", {"algorithm": "cma_es", "env": {"name": "pendulum"}, "total_timesteps": 3000, "network": SMALL,
                    "cma_es": {"normalize_observations": True}}),
    # CNN policies on 32x32 pixels: uint8 images in, rdsim's scaling and layout inside the graph
    ("ppo_cnn", {"algorithm": "ppo", "env": {"name": "jaka_button", "is_discrete": True, "observation": "raw_pixels",
                                            "image_width": 32, "image_height": 32},
                 "num_envs": 2, "total_timesteps": 128, "network": {"cnn": {"channels": [8, 8], "kernels": [4, 3],
                                                                             "strides": [2, 1], "fc": [32]}},
                 "ppo": {"n_steps": 64, "batch_size": 64}}),
    ("dqn_cnn", {"algorithm": "dqn", "env": {"name": "jaka_button", "is_discrete": True, "observation": "raw_pixels",
                                            "image_width": 32, "image_height": 32},
                 "total_timesteps": 300, "network": {"cnn": {"channels": [8], "kernels": [4], "strides": [2], "fc": [32]}},
                 "dqn": {"learning_starts": 100, "batch_size": 32, "buffer_size": 1000}}),
]


@pytest.mark.parametrize("name,config", CASES, ids=[c[0] for c in CASES])
def test_onnx_actions_are_rdsims(name, config, tmp_path):
    rdsim.train(dict(config, seed=1), log_dir=str(tmp_path / "run"), quiet=True)
    model = rdsim.load_model(tmp_path / "run" / "model.bin")
    path = tmp_path / f"{name}.onnx"
    assert model.export_onnx(str(path)) == path.stat().st_size
    onnx.checker.check_model(onnx.load(str(path)))

    space = model.observation_space
    rng = np.random.default_rng(7)
    if space.dtype == np.uint8:
        observations = rng.integers(0, 256, size=(1000, *space.shape), dtype=np.uint8)
    else:
        observations = rng.normal(size=(1000, *space.shape)).astype(np.float32)
    session = onnxruntime.InferenceSession(str(path), providers=["CPUExecutionProvider"])
    (onnx_actions,) = session.run(["action"], {"observation": observations})
    expected = model.predict(observations)
    if isinstance(model.action_space, gymnasium.spaces.Discrete):
        assert onnx_actions.dtype == np.int64
        np.testing.assert_array_equal(onnx_actions, expected)
    else:
        assert onnx_actions.shape == expected.shape
        assert np.max(np.abs(onnx_actions - expected)) <= 1e-5


def test_cli_export_and_errors(tmp_path):
    binary = str(rdsim_binary())
    rdsim.train(dict(CASES[0][1], seed=2), log_dir=str(tmp_path / "run"), quiet=True)
    out = subprocess.run([binary, "export", str(tmp_path / "run" / "model.bin"), "--onnx", str(tmp_path / "p.onnx")],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "checked: its actions are rdsim's on 256 observations" in out.stdout
    meta = {p.key: p.value for p in onnx.load(str(tmp_path / "p.onnx")).metadata_props}
    assert meta["algorithm"] == "ppo" and meta["env"] == "jaka_button"

    damaged = tmp_path / "damaged.bin"
    data = bytearray((tmp_path / "run" / "model.bin").read_bytes())
    data[len(data) // 2] ^= 0xFF
    damaged.write_bytes(bytes(data))
    for model, why in ((damaged, "damaged"), (tmp_path / "missing.bin", "missing.bin")):
        out = subprocess.run([binary, "export", str(model), "--onnx", str(tmp_path / "x.onnx")], capture_output=True,
                             text=True, timeout=60)
        assert out.returncode == 1 and why in out.stderr and len(out.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "x.onnx").exists()
    out = subprocess.run([binary, "export", str(tmp_path / "run" / "model.bin"), "--onnx", ""], capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 1 and "--onnx: expected a file name" in out.stderr

    rdsim.train({"algorithm": "random", "env": {"name": "cartpole"}, "total_timesteps": 200, "seed": 1},
                log_dir=str(tmp_path / "random"), quiet=True)
    with pytest.raises(rdsim.Error, match="no policy to export"):
        rdsim.load_model(tmp_path / "random" / "model.bin").export_onnx(str(tmp_path / "r.onnx"))
