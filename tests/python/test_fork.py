"""rdsim after fork(): a vector env's worker threads stay in the process that made it, so a forked
child that steps it gets one clear error at once (never a hang); single envs work in forked children,
vector envs made in a spawned child work, and SB3's SubprocVecEnv of rdsim.make envs trains PPO."""
import multiprocessing as mp

import numpy as np
import pytest

import rdsim

TRIES = 20
TIMEOUT_S = 30  # far above a step: only a hang reaches it


def _step_in_child(env, actions, queue):
    try:
        env.step(actions)
        queue.put("stepped")
    except rdsim.Error as e:
        queue.put("error: " + str(e))


def _run_child(ctx, target, *args):
    queue = ctx.Queue()
    child = ctx.Process(target=target, args=(*args, queue))
    child.start()
    child.join(TIMEOUT_S)
    hung = child.is_alive()
    if hung:
        child.kill()
        child.join()
    return hung, (queue.get(timeout=5) if not hung else None)


def test_a_vector_env_stepped_in_a_forked_child_raises_at_once():
    venv = rdsim.make_vec("rdsim/JakaButton-v0", 4, num_threads=2, seed=0)
    venv.reset(seed=0)
    ctx = mp.get_context("fork")
    for _ in range(TRIES):
        hung, result = _run_child(ctx, _step_in_child, venv, np.zeros(4, dtype=np.int64))
        assert not hung
        assert result.startswith("error: ") and "a fork of it" in result and "spawn" in result
    venv.step(np.zeros(4, dtype=np.int64))  # the parent's workers are untouched
    venv.close()


def test_a_single_env_works_in_a_forked_child():
    env = rdsim.make("rdsim/JakaButton-v0")
    env.reset(seed=0)
    ctx = mp.get_context("fork")
    for _ in range(TRIES):
        hung, result = _run_child(ctx, _step_in_child, env, 1)
        assert not hung and result == "stepped"
    env.close()


def _make_vec_in_child(queue):
    venv = rdsim.make_vec("rdsim/JakaButton-v0", 2, num_threads=2, seed=1)
    venv.reset(seed=1)
    venv.step(np.zeros(2, dtype=np.int64))
    venv.close()
    queue.put("stepped")


def test_a_vector_env_made_in_a_spawned_child_works():
    ctx = mp.get_context("spawn")
    hung, result = _run_child(ctx, _make_vec_in_child)
    assert not hung and result == "stepped"


def test_sb3_subproc_vec_env_of_rdsim_envs_trains_ppo():
    torch = pytest.importorskip("torch")
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import SubprocVecEnv

    torch.set_num_threads(1)
    venv = SubprocVecEnv([lambda: rdsim.make("rdsim/CartPole-v1") for _ in range(2)], start_method="fork")
    model = PPO("MlpPolicy", venv, n_steps=64, batch_size=64, n_epochs=1, seed=0, verbose=0)
    model.learn(total_timesteps=256)
    assert model.num_timesteps >= 256
    venv.close()
