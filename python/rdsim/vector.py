"""``rdsim.make_vec``: the C++ VecEnv as a ``gymnasium.vector.VectorEnv``."""
from __future__ import annotations

import json
import os
from typing import Any, Optional

import gymnasium
import numpy as np
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from . import _rdsim
from ._ids import env_id as _env_id
from ._ids import env_name
from .env import _check_reset_options, _rdsim_seed_check
from .spaces import action_space, goal_dict, observation_parts, observation_space

_INFO_KEYS = ("success", "collision", "out_of_bounds", "distance")


class RdsimVectorEnv(gymnasium.vector.VectorEnv):
    """``num_envs`` copies of an rdsim env stepped together in C++ (``rdsim::VecEnv``).

    The envs are split into ``num_threads`` contiguous blocks, each stepped by one worker: threads,
    or for pixel envs drawn on the CPU, child processes (``env_workers="auto"``, as ``rdsim train``
    does). Results do not depend on the number of workers. The GIL is released while the envs step.

    **Autoreset**: ``metadata["autoreset_mode"]`` is ``AutoresetMode.SAME_STEP``. An env whose
    episode ends in a step is reset within that step: the returned observation is the new episode's
    first, and ``info["final_obs"][i]`` / ``info["final_info"]`` hold the observation and info that
    ended the episode (masks ``info["_final_obs"]``, ``info["final_info"]["_success"]`` ...).

    **Memory**: the envs write their observations straight into one batch array owned by this
    object (no per-env Python objects). With ``copy=True`` (the default) ``reset``/``step`` return
    copies of it; with ``copy=False`` they return the batch array itself, which the next step
    overwrites (as ``SyncVectorEnv(copy=False)``). Rewards, terminations and truncations come the
    same way.

    **Processes**: the worker threads live in the process that made the vector env and do not survive
    ``fork()``; used in a forked child (``multiprocessing``'s default start method on Linux), every
    step or reset raises :class:`rdsim.Error` at once instead of waiting for them (with one thread
    and no worker processes there is nothing to wait for, and it works). Make the vector env in the
    process that steps it, or start children with ``spawn``. Single envs (``rdsim.make``) work in
    forked children.

    **Seeds**: ``reset(seed=s)`` seeds env ``i`` with ``rdsim.env_seed(s, i)`` (the C++ VecEnv's
    derivation); later episodes continue each env's own stream. ``reset()`` without a seed draws one.
    """

    metadata: dict[str, Any] = {"autoreset_mode": AutoresetMode.SAME_STEP, "render_modes": []}

    def __init__(
        self,
        env_id: str,
        num_envs: int,
        num_threads: Optional[int] = None,
        *,
        seed: Optional[int] = None,
        env_workers: str = "auto",
        copy: bool = True,
        **options: Any,
    ) -> None:
        name = env_name(env_id)
        gym_id = _env_id(name)
        self._where = f'rdsim.make_vec("{gym_id}")'
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)):
            raise _rdsim.Error(f"{self._where}: num_envs: expected an integer in [1, 4096], got {num_envs!r}")
        if num_threads is None:
            num_threads = max(1, min(int(num_envs), os.cpu_count() or 1))
        if isinstance(num_threads, bool) or not isinstance(num_threads, (int, np.integer)):
            raise _rdsim.Error(f"{self._where}: num_threads: expected an integer in [1, 1024], got {num_threads!r}")
        if not isinstance(env_workers, str):
            raise _rdsim.Error(f"{self._where}: env_workers: expected one of auto, threads, processes, got {env_workers!r}")
        if seed is not None:
            _rdsim_seed_check(self._where, seed)
        first_seed = int(seed) if seed is not None else int(np.random.SeedSequence().generate_state(1, np.uint64)[0])
        self._vec = _rdsim.VecEnv(name, options, self._where, int(num_envs), int(num_threads), first_seed, env_workers)
        spec = self._vec.spec
        self.num_envs = int(num_envs)
        self.single_observation_space = observation_space(spec)
        #: What each value of one env's observation is, as :attr:`rdsim.RdsimEnv.observation_parts`.
        self.observation_parts: dict[str, slice] = observation_parts(spec)
        #: A goal env's layout and reward (``None`` for other envs): observations are dicts of
        #: ``observation``, ``achieved_goal`` and ``desired_goal`` arrays, one row per env.
        self.goal: Optional[dict] = spec["goal"]
        self._image_shape = tuple(spec["observation_shape"])
        if self.goal is not None:
            self.compute_reward = self._compute_reward  # goal envs only (as rdsim.make's)
        self.single_action_space = action_space(spec)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.copy = bool(copy)
        self.render_mode = None
        self.metadata = dict(type(self).metadata)
        #: The resolved env config (every key the env reads, with its value).
        self.config: dict[str, Any] = json.loads(self._vec.config_json)
        self._observations = self._vec.observations()
        self._seeded = seed is not None
        if gym_id in gymnasium.registry:
            self.spec = gymnasium.registry[gym_id]

    # --- Gymnasium API ---------------------------------------------------------------------------
    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        """Resets every env; returns ``(observations, {})``. ``seed`` must be one int (or None)."""
        _check_reset_options(self._where, options)
        if seed is not None:
            _rdsim_seed_check(self._where, seed)
            self._np_random, self._np_random_seed = gymnasium.utils.seeding.np_random(int(seed))
            vec_seed = int(seed)
        else:
            vec_seed = int(self.np_random.integers(0, 2**63))
        self._vec.reset(vec_seed)
        return self._observation_out(self._observations), {}

    def step(self, actions):
        """Steps every env; ``actions`` is an integer array (num_envs,) or a float array (num_envs, dim)."""
        self._vec.step(actions)
        return self._results()

    def step_async(self, actions) -> None:
        """Starts a step on a helper thread and returns at once (EnvPool style); then ``step_wait()``."""
        self._vec.step_async(actions)

    def step_wait(self):
        """Waits for the step started by ``step_async``; returns what ``step`` returns."""
        self._vec.step_wait()
        return self._results()

    def close_extras(self, **kwargs: Any) -> None:
        """Stops the workers and frees the envs; later calls raise :class:`rdsim.Error`."""
        vec = getattr(self, "_vec", None)
        if vec is not None and not vec.closed:
            self._observations = None
            vec.close()

    def render(self):
        """Vector envs draw nothing (make single envs with ``render_mode="rgb_array"`` to watch)."""
        return None

    # --- rdsim extras ----------------------------------------------------------------------------
    @property
    def num_threads(self) -> int:
        """Workers stepping the envs (threads or processes)."""
        return self._vec.num_threads

    @property
    def uses_processes(self) -> bool:
        """True when the blocks after the first are stepped in child processes."""
        return self._vec.processes

    @property
    def timesteps(self) -> int:
        """Env steps taken so far, all envs together."""
        return self._vec.timesteps

    def _compute_reward(self, achieved_goal, desired_goal, info=None):
        """A goal env's rewards for goal pairs (last axis: the goal's points, 3 values each), batched
        over the leading axes: what ``step`` gives (:meth:`rdsim.RdsimEnv.compute_reward`)."""
        reward = _rdsim.compute_reward(self.goal, np.asarray(achieved_goal), np.asarray(desired_goal))
        return float(reward) if reward.ndim == 0 else reward

    def __repr__(self) -> str:
        return f"RdsimVectorEnv({_env_id(self.config.get('name', '?'))}, num_envs={self.num_envs})"

    # --- internals -------------------------------------------------------------------------------
    def _out(self, array: np.ndarray) -> np.ndarray:
        return array.copy() if self.copy else array

    def _observation_out(self, flat):
        if self.goal is None:
            return self._out(flat)
        return goal_dict(self.goal, flat, copy=self.copy, shape=self._image_shape)

    def _results(self):
        """The last step's tuple, built by the binding; goal envs' observations become dicts."""
        out = self._vec.results(self.copy)
        if self.goal is None:
            return out
        obs, rewards, terminations, truncations, infos = out
        infos["is_success"], infos["_is_success"] = infos["success"], infos["_success"]
        if "final_obs" in infos:
            final_obs = infos["final_obs"]
            for i in infos["_final_obs"].nonzero()[0]:
                final_obs[i] = goal_dict(self.goal, final_obs[i], copy=False, shape=self._image_shape)
        return goal_dict(self.goal, obs, copy=False, shape=self._image_shape), rewards, terminations, truncations, infos


def make_vec(env_id: str, num_envs: int = 1, num_threads: Optional[int] = None, **options: Any) -> RdsimVectorEnv:
    """``num_envs`` rdsim envs stepped together in C++, as a ``gymnasium.vector.VectorEnv``.

    ``num_threads`` workers (default: min(num_envs, CPU count)); keyword-only extras: ``seed`` (first
    episodes' seed), ``env_workers`` ("auto", "threads", "processes"), ``copy`` (return copies, default
    True); every other keyword is an env config key, as for :func:`rdsim.make`.
    """
    return RdsimVectorEnv(env_id, num_envs, num_threads, **options)


def vector_env_for_gymnasium(env_id: str, num_envs: int = 1, **kwargs: Any) -> RdsimVectorEnv:
    """Gymnasium's vector entry point for the rdsim ids (``gymnasium.make_vec``)."""
    return RdsimVectorEnv(env_id, num_envs, **kwargs)
