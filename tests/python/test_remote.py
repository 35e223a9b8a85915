"""rdsim.RemoteEnv against `rdsim serve` on loopback: the same trajectory as rdsim.make, and the example."""
import sys

import numpy as np
import pytest

import rdsim
from conftest import ROOT, rdsim_binary

sys.path.insert(0, str(ROOT / "tools"))


def test_remote_env_matches_local(server):
    remote = rdsim.RemoteEnv(server.address, "rdsim/JakaButton-v0", max_steps=30, random_target=True)
    local = rdsim.make("rdsim/JakaButton-v0", max_steps=30, random_target=True)
    assert remote.observation_space == local.observation_space and remote.action_space == local.action_space
    assert remote.config == local.config
    assert remote.observation_parts == local.unwrapped.observation_parts == {
        "target_from_effector": slice(0, 3), "effector_position": slice(3, 6)}
    a, _ = remote.reset(seed=4)
    b, _ = local.reset(seed=4)
    np.testing.assert_array_equal(a, b)
    rng = np.random.default_rng(1)
    for _ in range(80):
        act = int(rng.integers(0, 6))
        ra, rb = remote.step(act), local.step(act)
        np.testing.assert_array_equal(ra[0], rb[0])
        assert ra[1:4] == rb[1:4]
        if ra[2] or ra[3]:
            np.testing.assert_array_equal(remote.reset()[0], local.reset()[0])
    remote.close()
    with pytest.raises(rdsim.Error):
        remote.step(0)


@pytest.mark.parametrize("channels", ["rgb", "depth"])
def test_remote_goal_env_with_camera_images_matches_local(server, channels):
    options = dict(observation="raw_pixels", image_width=32, image_height=24, image_channels=channels, max_steps=6)
    remote = rdsim.RemoteEnv(server.address, "rdsim/JakaPush-v0", **options)
    local = rdsim.make("rdsim/JakaPush-v0", **options)
    assert remote.observation_space == local.observation_space
    a, _ = remote.reset(seed=3)
    b, _ = local.reset(seed=3)
    for _ in range(6):
        assert a.keys() == b.keys()
        for key in a:
            np.testing.assert_array_equal(a[key], b[key])
        act = np.array([0.2, 0.5, -1.0], np.float32)
        (a, ra, *_), (b, rb, *_) = remote.step(act), local.step(act)
        assert ra == rb
    remote.close()
    local.close()


def test_remote_errors(server):
    with pytest.raises(rdsim.Error, match="max_steps"):
        rdsim.RemoteEnv(server.address, "rdsim/CartPole-v1", max_steps=0)
    env = rdsim.RemoteEnv(server.address, "rdsim/CartPole-v1")
    env.reset(seed=0)
    for bad in (7, -1, 1.5, "x", np.array([1, 0])):
        with pytest.raises(rdsim.Error):
            env.step(bad)
    env.close()


def test_remote_random_agent_example(server):
    import remote_random_agent

    result = remote_random_agent.main([server.address, "--env", "rdsim/CartPole-v1", "--steps", "100"])
    assert result["episodes"] >= 1
