"""make_vec: the C++ VecEnv through Gymnasium's VectorEnv API, and identical trajectories through make,
make_vec with 1 and 2 threads (the C++ VecEnv stepped directly) for the same seed."""
import gymnasium
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import rdsim


def test_spaces_and_metadata():
    venv = rdsim.make_vec("rdsim/JakaButton-v0", 4, num_threads=2)
    assert venv.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
    assert venv.num_envs == 4 and venv.num_threads == 2
    assert venv.single_action_space == gymnasium.spaces.Discrete(6)
    assert venv.action_space == gymnasium.spaces.MultiDiscrete([6, 6, 6, 6])
    obs, info = venv.reset(seed=1)
    assert obs.shape == (4,) + venv.single_observation_space.shape and obs.dtype == np.float32
    assert venv.observation_space.contains(obs)
    venv.close()


def test_same_step_autoreset_and_final_obs():
    venv = rdsim.make_vec("rdsim/CartPole-v1", 3, num_threads=1, max_steps=5)
    obs, _ = venv.reset(seed=2)
    for t in range(5):
        prev = obs
        obs, rew, term, trunc, info = venv.step(np.zeros(3, dtype=np.int64))
        assert rew.dtype == np.float32 and term.dtype == np.bool_ and trunc.dtype == np.bool_
    ended = term | trunc
    assert ended.all() and info["_final_obs"].all() and info["final_info"]["_success"].all()
    # The final observation is the step's result; the returned one the next episode's first.
    for i in range(3):
        assert info["final_obs"][i].shape == (4,)
        assert not np.array_equal(info["final_obs"][i], obs[i])
    assert set(info) >= {"success", "_success", "collision", "out_of_bounds", "distance", "final_obs", "final_info"}
    venv.close()


def test_step_async_matches_step():
    a = rdsim.make_vec("rdsim/JakaButton-v0", 4, num_threads=2, max_steps=20)
    b = rdsim.make_vec("rdsim/JakaButton-v0", 4, num_threads=2, max_steps=20)
    a.reset(seed=5)
    b.reset(seed=5)
    rng = np.random.default_rng(0)
    for _ in range(60):
        act = rng.integers(0, 6, size=4)
        ra = a.step(act)
        b.step_async(act)
        rb = b.step_wait()
        for x, y in zip(ra[:4], rb[:4]):
            np.testing.assert_array_equal(x, y)
    a.close()
    b.close()


def test_copy_false_returns_the_batch_itself():
    venv = rdsim.make_vec("rdsim/CartPole-v1", 2, copy=False)
    obs, _ = venv.reset(seed=0)
    obs2, *_ = venv.step(np.array([0, 1]))
    assert obs2 is obs or np.shares_memory(obs, obs2)
    venv.close()
    # The array outlives close(): its memory stays valid.
    assert np.isfinite(obs).all()


def test_returned_arrays_are_the_callers_and_final_obs_is_none_where_no_episode_ended():
    venv = rdsim.make_vec("rdsim/CartPole-v1", 3, num_threads=1, max_steps=4)
    venv.reset(seed=1)
    kept = [venv.step(np.array([0, 1, 0])) for _ in range(3)]
    saved = [tuple(np.copy(x) for x in out[:4]) + ({k: np.copy(out[4][k]) for k in ("success", "distance")},)
             for out in kept]
    for _ in range(6):  # later steps (and episode ends) leave the returned arrays alone
        obs, rew, term, trunc, info = venv.step(np.array([1, 1, 0]))
    for out, copy in zip(kept, saved):
        for x, y in zip(out[:4], copy[:4]):
            np.testing.assert_array_equal(x, y)
        for key in ("success", "distance"):
            np.testing.assert_array_equal(out[4][key], copy[4][key])
    # Episodes of 4 steps: the 9th step ends no episode, the 8th ended all three.
    assert "final_obs" not in info
    venv.reset(seed=1)
    for t in range(4):
        obs, rew, term, trunc, info = venv.step(np.array([0, 1, 0]))
    assert list(info["_final_obs"]) == [True, True, True]
    assert info["final_info"]["success"] is info["success"]
    venv.close()
    venv = rdsim.make_vec("rdsim/CartPole-v1", 4, num_threads=1)
    venv.reset(seed=0)
    for _ in range(500):  # pushing one way ends some episodes before the others
        obs, rew, term, trunc, info = venv.step(np.array([0, 0, 1, 1]))
        if (term | trunc).any() and not (term | trunc).all():
            break
    ended = term | trunc
    np.testing.assert_array_equal(info["_final_obs"], ended)
    assert 0 < ended.sum() < 4
    for i in range(4):
        assert (info["final_obs"][i] is None) == (not ended[i])
    venv.close()


def test_gymnasium_make_vec_uses_the_cpp_vector_env():
    venv = gymnasium.make_vec("rdsim/CartPole-v1", num_envs=3)
    assert isinstance(venv, rdsim.RdsimVectorEnv)
    venv.reset(seed=0)
    venv.step(np.zeros(3, dtype=np.int64))
    venv.close()


def _single_env_trajectory(env_id, options, n, seed, actions):
    """Each env alone (rdsim.make), seeded as the VecEnv seeds env i, reset by hand at episode ends."""
    envs = [rdsim.make(env_id, **options) for _ in range(n)]
    obs = np.stack([e.reset(seed=rdsim.env_seed(seed, i))[0] for i, e in enumerate(envs)])
    out = [obs]
    for act in actions:
        rows, rews, terms, truncs, finals = [], [], [], [], []
        for i, e in enumerate(envs):
            o, r, te, tr, _ = e.step(act[i])
            finals.append(o if (te or tr) else None)
            if te or tr:
                o, _ = e.reset()
            rows.append(o)
            rews.append(r)
            terms.append(te)
            truncs.append(tr)
        out.append((np.stack(rows), np.array(rews, np.float32), np.array(terms), np.array(truncs), finals))
    for e in envs:
        e.close()
    return out


def _vector_trajectory(env_id, options, n, threads, seed, actions):
    venv = rdsim.make_vec(env_id, n, num_threads=threads, **options)
    out = [venv.reset(seed=seed)[0]]
    for act in actions:
        obs, rew, term, trunc, info = venv.step(act)
        finals = [info["final_obs"][i] if "final_obs" in info and info["_final_obs"][i] else None for i in range(n)]
        out.append((obs, rew, term, trunc, finals))
    venv.close()
    return out


@pytest.mark.parametrize(
    "env_id,options,steps",
    [
        ("rdsim/CartPole-v1", {}, 400),
        ("rdsim/JakaButton-v0", {"max_steps": 40, "random_target": True}, 300),
        ("rdsim/Pendulum-v1", {"is_discrete": False, "max_steps": 50}, 300),
    ],
)
def test_same_seed_same_trajectory_make_vs_make_vec(env_id, options, steps):
    n, seed = 4, 11
    probe = rdsim.make(env_id, **options)
    rng = np.random.default_rng(3)
    if isinstance(probe.action_space, gymnasium.spaces.Discrete):
        actions = [rng.integers(0, probe.action_space.n, size=n) for _ in range(steps)]
    else:
        lo, hi = probe.action_space.low, probe.action_space.high
        actions = [rng.uniform(lo, hi, size=(n,) + lo.shape).astype(np.float32) for _ in range(steps)]
    probe.close()
    single = _single_env_trajectory(env_id, options, n, seed, actions)
    one = _vector_trajectory(env_id, options, n, 1, seed, actions)
    two = _vector_trajectory(env_id, options, n, 2, seed, actions)
    assert steps * n >= 1000
    resets = 0
    np.testing.assert_array_equal(single[0], one[0])
    np.testing.assert_array_equal(one[0], two[0])
    for t in range(1, steps + 1):
        for a, b in ((single[t], one[t]), (one[t], two[t])):
            for x, y in zip(a[:4], b[:4]):
                np.testing.assert_array_equal(x, y)
            for fa, fb in zip(a[4], b[4]):
                assert (fa is None) == (fb is None)
                if fa is not None:
                    np.testing.assert_array_equal(fa, fb)
        resets += int((one[t][2] | one[t][3]).sum())
    assert resets > 0


def test_pixel_envs_in_worker_processes_match_threads():
    options = {"observation": "raw_pixels", "image_width": 36, "image_height": 36, "max_steps": 15}
    rng = np.random.default_rng(4)
    actions = [rng.integers(0, 6, size=4) for _ in range(40)]
    procs = rdsim.make_vec("rdsim/JakaButton-v0", 4, num_threads=2, **options)
    assert procs.uses_processes
    threads = rdsim.make_vec("rdsim/JakaButton-v0", 4, num_threads=1, **options)
    a, b = procs.reset(seed=9)[0], threads.reset(seed=9)[0]
    np.testing.assert_array_equal(a, b)
    for act in actions:
        ra, rb = procs.step(act), threads.step(act)
        for x, y in zip(ra[:4], rb[:4]):
            np.testing.assert_array_equal(x, y)
    procs.close()
    threads.close()
