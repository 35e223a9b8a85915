"""Domain randomization from Python: the env's "randomize" option through rdsim.make and make_vec
(the same noise for the same seed), and a bad value as one rdsim.Error naming the key."""
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
    assert a.config["randomize"] == {"observation_noise": 0.01, "action_latency": 1}
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
