"""Stable-Baselines3 on ``rdsim.make_vec``: :class:`SB3VecEnv` adapts the Gymnasium vector env to
SB3's ``VecEnv`` interface (needs stable-baselines3)."""
from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np
from stable_baselines3.common.vec_env.base_vec_env import VecEnv

from .vector import RdsimVectorEnv


class SB3VecEnv(VecEnv):
    """An :class:`rdsim.RdsimVectorEnv` as an SB3 ``VecEnv``.

    SB3's vector envs reset in the same step, as rdsim's does: ``infos[i]["terminal_observation"]``
    is the observation that ended env ``i``'s episode, ``infos[i]["TimeLimit.truncated"]`` says it
    was cut by the step limit, and ``infos[i]["is_success"]`` is the task's success flag (SB3 logs
    its mean as ``rollout/success_rate``). Wrap it in ``VecMonitor`` for episode returns.
    """

    def __init__(self, venv: RdsimVectorEnv) -> None:
        self.venv = venv
        super().__init__(venv.num_envs, venv.single_observation_space, venv.single_action_space)

    def reset(self):
        seed = self._seeds[0] if self._seeds and self._seeds[0] is not None else None
        obs, _ = self.venv.reset(seed=seed)
        self._reset_seeds()
        self._reset_options()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self.venv.step_async(actions)

    def step_wait(self):
        obs, rewards, terminated, truncated, info = self.venv.step_wait()
        dones = terminated | truncated
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        if dones.any():
            final_success = info["final_info"]["success"]
            for i in np.flatnonzero(dones):
                infos[i]["terminal_observation"] = info["final_obs"][i]
                infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
                infos[i]["is_success"] = bool(final_success[i])
        return obs, rewards, dones, infos

    def close(self) -> None:
        self.venv.close()

    def get_attr(self, attr_name: str, indices=None) -> list[Any]:
        return [getattr(self.venv, attr_name)] * len(self._get_indices(indices))

    def set_attr(self, attr_name: str, value: Any, indices=None) -> None:
        raise AttributeError(f"rdsim's vector env has no per-env attribute {attr_name!r} to set")

    def env_method(self, method_name: str, *method_args, indices=None, **method_kwargs) -> list[Any]:
        # compute_reward is the env class's (the same for every env), what SB3's HerReplayBuffer calls.
        if method_name == "compute_reward" and hasattr(self.venv, "compute_reward"):
            reward = self.venv.compute_reward(*method_args, **method_kwargs)
            return [reward] * len(self._get_indices(indices))
        raise AttributeError(f"rdsim's vector env has no per-env method {method_name!r}")

    def env_is_wrapped(self, wrapper_class, indices=None) -> list[bool]:
        return [False] * len(self._get_indices(indices))

    def get_images(self) -> Sequence[Optional[np.ndarray]]:
        return [None] * self.num_envs
