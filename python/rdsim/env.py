"""``rdsim.make``: one rdsim env in this process, as a ``gymnasium.Env``."""
from __future__ import annotations

import copy
import json
from typing import Any, Optional

import gymnasium
import numpy as np

from . import _rdsim
from ._ids import env_id as _env_id
from ._ids import env_name
from .spaces import action_space, goal_dict, observation_parts, observation_space, render_fps


class RdsimEnv(gymnasium.Env):
    """An rdsim env (the C++ ``rdsim::Env``) with Gymnasium's API.

    Made by :func:`rdsim.make` or ``gymnasium.make("rdsim/...")``. ``options`` are the keys of the
    ``env`` object of a training config (``rdsim config-reference``), checked by the same reader with
    the same messages: an unknown key, a key the env does not read or a value out of range raises
    :class:`rdsim.Error`.

    - ``reset(seed=...)`` seeds the env's own generator (``Env::reset(seed)``); without a seed the
      env's stream continues, so a sequence of resets after one seeded reset is reproducible.
    - ``step`` returns ``(observation, reward, terminated, truncated, info)``; ``info`` holds
      ``success``, ``collision``, ``out_of_bounds`` (bools) and ``distance`` (metres; 0 for the
      classic-control envs). ``truncated`` comes from the env's own ``max_steps``.
    - ``render()`` returns an RGB array (``render_height`` x ``render_width`` x 3) when made with
      ``render_mode="rgb_array"`` (robot envs only), else ``None``.
    - Goal envs (the manipulation tasks: ``rdsim/JakaPush-v0`` ...) follow Gymnasium-Robotics' GoalEnv:
      observations are dicts of ``observation``, ``achieved_goal`` and ``desired_goal``, ``info`` also
      holds ``is_success``, and ``compute_reward(achieved_goal, desired_goal, info)`` gives the reward
      ``step`` would for any goals, batched over leading axes (what hindsight experience replay needs).
    """

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 30}

    def __init__(self, env_id: str, render_mode: Optional[str] = None, **options: Any) -> None:
        name = env_name(env_id)
        self._where = f'rdsim.make("{_env_id(name)}")'
        if render_mode == "none":  # the env config's word for None (env.config, a model's config["env"])
            render_mode = None
        if render_mode is not None:
            if render_mode != "rgb_array":
                raise _rdsim.Error(
                    f'{self._where}: render_mode: expected None, "none" or "rgb_array", got {render_mode!r}')
            options["render_mode"] = render_mode
        self._env = _rdsim.Env(name, options, self._where)
        spec = self._env.spec
        self.observation_space = observation_space(spec)
        #: What each value of a vector observation is: part name -> slice of the flat vector
        #: (``{}`` for images); randomize's ``observation_noise_parts`` takes these names.
        self.observation_parts: dict[str, slice] = observation_parts(spec)
        #: A goal env's layout and reward (``None`` for other envs).
        self.goal: Optional[dict] = spec["goal"]
        self._image_shape = tuple(spec["observation_shape"])
        if self.goal is not None:
            # Only goal envs have compute_reward (checkers such as SB3's take it to mean a GoalEnv).
            self.compute_reward = self._compute_reward
        self.action_space = action_space(spec)
        self.render_mode = render_mode
        #: The resolved env config: every key the env reads, with the value it uses.
        self.config: dict[str, Any] = json.loads(self._env.config_json)
        #: Simulated seconds per step (0 for envs without a physics clock).
        self.control_dt: float = float(spec["control_dt"])
        #: The env's truncation limit in steps.
        self.max_episode_steps: int = int(spec["max_episode_steps"])
        self.metadata = {
            "render_modes": ["rgb_array"] if _supports_pixels(name) else [],
            "render_fps": render_fps(spec),
        }

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        """Starts an episode; returns ``(observation, {})``."""
        _check_reset_options(self._where, options)
        if seed is not None:
            _rdsim_seed_check(self._where, seed)
        super().reset(seed=seed)
        return self._observation(self._env.reset(seed)), {}

    def step(self, action):
        """One control step; ``action`` is an int (Discrete) or a float array (Box)."""
        obs, reward, terminated, truncated, success, collision, out_of_bounds, distance = self._env.step(action)
        info = {"success": success, "collision": collision, "out_of_bounds": out_of_bounds, "distance": distance}
        if self.goal is not None:
            info["is_success"] = success
        return self._observation(obs), float(reward), terminated, truncated, info

    def _compute_reward(self, achieved_goal, desired_goal, info=None):
        """A goal env's reward for ``achieved_goal`` / ``desired_goal`` (arrays whose last axis holds the
        goal's points, 3 values each), batched over the leading axes; equal to what ``step`` returns.
        ``info`` is accepted for Gymnasium-Robotics' signature and not read."""
        reward = _rdsim.compute_reward(self.goal, np.asarray(achieved_goal), np.asarray(desired_goal))
        return float(reward) if reward.ndim == 0 else reward

    def _observation(self, flat):
        return flat if self.goal is None else goal_dict(self.goal, flat, copy=False, shape=self._image_shape)

    def render(self) -> Optional[np.ndarray]:
        """An RGB frame (``render_mode="rgb_array"``), else ``None``."""
        return self._env.render()

    def close(self) -> None:
        """Frees the env (its physics world, its renderer); later calls raise :class:`rdsim.Error`."""
        env = getattr(self, "_env", None)
        if env is not None and not env.closed:
            env.close()

    def __repr__(self) -> str:
        return f"<RdsimEnv {_env_id(env_name_of(self))}>"


def env_name_of(env: RdsimEnv) -> str:
    return env.config.get("name", "?")


def _supports_pixels(name: str) -> bool:
    return any(entry[0] == name and entry[2] for entry in _rdsim.registry())


def _check_reset_options(where: str, options: Optional[dict]) -> None:
    if options is None:
        return
    if not isinstance(options, dict):
        raise _rdsim.Error(f"{where}: reset: options: expected None or a dict, got a {type(options).__name__}")
    if options:
        raise _rdsim.Error(f"{where}: reset: options: rdsim envs take no reset options, got {sorted(map(str, options))}")


def _rdsim_seed_check(where: str, seed: Any) -> None:
    # The same rule as the C++ side, before Gymnasium's own generator is seeded with it.
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)) or not 0 <= int(seed) < 2**64:
        raise _rdsim.Error(f"{where}: reset: seed: expected None or an integer in [0, 2^64 - 1], got {seed!r}")


def make(env_id: str, render_mode: Optional[str] = None, *, remote: Optional[str] = None,
         server_key: Optional[str] = None, client_key: Optional[str] = None, timeout: Optional[float] = None,
         **options: Any) -> gymnasium.Env:
    """An rdsim env as a ``gymnasium.Env`` (no Gymnasium wrappers; ``gymnasium.make`` adds its own).

    ``env_id`` is a Gymnasium id (``"rdsim/JakaButton-v0"``) or a registry name (``"jaka_button"``);
    ``options`` are env config keys, e.g. ``observation="raw_pixels", image_width=64, is_discrete=False``.

    With ``remote="tcp://host:port"`` the env runs on that ``rdsim serve`` and the result is an
    :class:`rdsim.RemoteEnv` (needs pyzmq) with the same spaces; ``server_key`` (the server's NAME.key)
    and ``client_key`` (this client's NAME.key_secret) encrypt the link, ``timeout`` is the seconds to
    wait for each reply (default 60). These three need ``remote``.
    """
    link = {"remote": remote, "server_key": server_key, "client_key": client_key, "timeout": timeout}
    link = {key: value for key, value in link.items() if value is not None}
    env = env_for_gymnasium(env_id, render_mode=render_mode, **link, **options)
    options = {**link, **options}  # for env.spec: gymnasium.make(env.spec) makes the same env
    gym_id = _env_id(env_name(env_id))
    if gym_id in gymnasium.registry:
        spec = copy.deepcopy(gymnasium.registry[gym_id])
        spec.kwargs = {"env_id": gym_id, **options}
        if render_mode is not None:
            spec.kwargs["render_mode"] = render_mode
        env.spec = spec
    return env


def _check_local_only(env_id: str, **remote_arguments: Any) -> None:
    """server_key, client_key and timeout belong to a remote env: refused without ``remote``."""
    given = [key for key, value in remote_arguments.items() if value is not None]
    if given:
        raise _rdsim.Error(f'rdsim.make("{_env_id(env_name(env_id))}"): {given[0]}: expected only with '
                           f'remote="tcp://host:port" (the address of an `rdsim serve`), got no remote')


def _remote_env(env_id: str, render_mode: Optional[str], remote: str, server_key: Optional[str],
                client_key: Optional[str], timeout: Optional[float], options: dict) -> gymnasium.Env:
    """:class:`rdsim.RemoteEnv` of ``env_id`` on the server at ``remote``."""
    where = f'rdsim.make("{_env_id(env_name(env_id))}", remote={remote!r})'
    if not isinstance(remote, str) or not remote:
        raise _rdsim.Error(f'{where}: remote: expected an address such as "tcp://host:port", got {remote!r}')
    if timeout is not None and (isinstance(timeout, bool) or not isinstance(timeout, (int, float))
                                or not 0 < timeout < float("inf")):
        raise _rdsim.Error(f"{where}: timeout: expected a number of seconds > 0, got {timeout!r}")
    if render_mode not in (None, "none"):
        raise _rdsim.Error(f"{where}: render_mode: expected None for a remote env (it does not render; "
                           f"RemoteEnv.cameras() returns images), got {render_mode!r}")
    try:
        from .remote import RemoteEnv
    except ImportError as e:
        raise _rdsim.Error(f"{where}: remote: needs pyzmq (pip install rdsim[remote]): {e}") from None
    extra = {} if timeout is None else {"timeout": timeout}
    return RemoteEnv(remote, env_id, server_key=server_key, client_key=client_key, **extra, **options)


def env_for_gymnasium(env_id: str, render_mode: Optional[str] = None, remote: Optional[str] = None,
                      server_key: Optional[str] = None, client_key: Optional[str] = None,
                      timeout: Optional[float] = None, **options: Any) -> gymnasium.Env:
    """Gymnasium's entry point for the rdsim ids (``gymnasium.make``), with :func:`make`'s arguments."""
    if remote is None:
        _check_local_only(env_id, server_key=server_key, client_key=client_key, timeout=timeout)
        return RdsimEnv(env_id, render_mode=render_mode, **options)
    return _remote_env(env_id, render_mode, remote, server_key, client_key, timeout, options)
