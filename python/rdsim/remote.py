"""``rdsim.RemoteEnv``: an env served by ``rdsim serve`` (docs/protocol.md), with Gymnasium's API.

Needs pyzmq (``pip install rdsim[remote]``). The link logic is tools/rdsim_client.py's, with
Gymnasium spaces and :class:`rdsim.Error` for every refusal, timeout or bad reply.
"""
from __future__ import annotations

import json
from typing import Any, Optional, Union

import gymnasium
import numpy as np
import zmq

from . import _rdsim
from ._ids import env_name
from ._rdsim import Error
from .spaces import goal_dict, observation_parts, observation_space

PROTOCOL_VERSION = 1
_DTYPES = {"float32": np.dtype("<f4"), "uint8": np.dtype("u1")}


def _key_field(path: str, label: str) -> bytes:
    try:
        with open(path, encoding="ascii") as f:
            for line in f:
                if line.startswith(label + " "):
                    return line.split(None, 1)[1].strip().encode("ascii")
    except OSError as e:
        raise Error(f"{path}: cannot read the key file ({e.strerror})") from None
    raise Error(f"{path}: no '{label} <key>' line (write key files with `rdsim keygen NAME`)")


def _local_spec(remote_spec: dict, arrays: dict) -> dict:
    """The observation part of a hello reply's spec in the C++ module's layout (rdsim.spaces reads it)."""
    obs = remote_spec["observation"]
    spec = {"observation_shape": obs["shape"], "observation_dtype": obs["dtype"], "goal": remote_spec.get("goal"),
            "observation_parts": obs.get("parts", []), "observation_vector_size": obs.get("vector_size", 0)}
    if obs["dtype"] != "uint8" or spec["observation_vector_size"]:
        spec["observation_low"], spec["observation_high"] = arrays["observation_low"], arrays["observation_high"]
    return spec


class RemoteEnv(gymnasium.Env):
    """One session on an ``rdsim serve`` at ``address`` ("tcp://host:port"), as a ``gymnasium.Env``.

    ``env`` is an id (``"rdsim/JakaButton-v0"``), a registry name, or a whole ``env`` config object
    (a dict with "name"); ``options`` are more env keys. The server validates them with the config
    reader's messages. Without keys the link is plain text (servers started with ``--insecure``, on
    loopback); with ``server_key`` (the server's NAME.key) and ``client_key`` (this client's
    NAME.key_secret) it is CurveZMQ-encrypted. Robot envs also offer ``position``, ``joints``,
    ``cameras`` and ``state`` (see docs/protocol.md). ``rdsim.make(env, remote=address, ...)`` makes one.

    The spaces are :func:`rdsim.make`'s: goal envs (``rdsim/JakaPush-v0`` ...) observe dicts of
    ``observation``, ``achieved_goal`` and ``desired_goal``, set ``info["is_success"]`` and have
    ``compute_reward(achieved_goal, desired_goal, info)``, computed here from the server's goal layout.
    """

    metadata: dict[str, Any] = {"render_modes": [], "render_fps": 30}

    def __init__(self, address: str, env: Union[str, dict], server_key: Optional[str] = None,
                 client_key: Optional[str] = None, timeout: float = 60.0, **options: Any) -> None:
        self.address, self.timeout = address, float(timeout)
        config = dict(env) if isinstance(env, dict) else {"name": env_name(env)}
        config.update(options)
        if (server_key is None) != (client_key is None):
            raise Error("RemoteEnv: give both server_key (the server's public key file) and client_key "
                        "(this client's secret key file), or neither")
        self._socket = zmq.Context.instance().socket(zmq.DEALER)
        self._socket.setsockopt(zmq.LINGER, 200)
        if server_key is not None:
            self._socket.curve_serverkey = _key_field(server_key, "public")
            self._socket.curve_publickey = _key_field(client_key, "public")
            self._socket.curve_secretkey = _key_field(client_key, "secret")
        try:
            self._socket.connect(address)
        except zmq.ZMQError as e:
            self._socket.close()
            self._socket = None
            raise Error(f'RemoteEnv: address: expected "tcp://host:port", got {address!r} ({e.strerror})') from None
        self._next_id = 1
        header, arrays = self.request({"request": "hello", "protocol": PROTOCOL_VERSION, "env": config})
        self.server = header.get("server")
        #: Every key of the env with the value the server uses.
        self.config: dict[str, Any] = header["env"]
        self.remote_spec = header["spec"]
        self.robot = header["robot"]  # None for envs without a robot (cartpole)
        local = _local_spec(self.remote_spec, arrays)
        self.observation_space = observation_space(local)
        #: What each value of the observation is, as :attr:`rdsim.RdsimEnv.observation_parts`.
        self.observation_parts: dict[str, slice] = observation_parts(local)
        #: A goal env's layout and reward (``None`` for other envs), as :attr:`rdsim.RdsimEnv.goal`.
        self.goal: Optional[dict] = self.remote_spec.get("goal")
        self._image_shape = tuple(self.remote_spec["observation"]["shape"])
        if self.goal is not None:
            # Only goal envs have compute_reward (checkers such as SB3's take it to mean a GoalEnv).
            self.compute_reward = self._compute_reward
        #: Simulated seconds per step and the truncation limit in steps, as rdsim.make's.
        self.control_dt: float = float(self.remote_spec["control_dt"])
        self.max_episode_steps: int = int(self.remote_spec["max_episode_steps"])
        act = self.remote_spec["action"]
        if act["discrete"]:
            self.action_space = gymnasium.spaces.Discrete(act["n"])
        else:
            self.action_space = gymnasium.spaces.Box(arrays["action_low"], arrays["action_high"], (act["dim"],), np.float32)

    # -- the protocol ---------------------------------------------------------------------------
    def request(self, header: dict):
        """Sends one request and returns (reply header, {name: array}); :class:`rdsim.Error` on refusal."""
        if self._socket is None:
            raise Error(f"{self.address}: the remote env is closed")
        header = dict(header, id=self._next_id)
        self._next_id += 1
        self._socket.send(json.dumps(header).encode("utf-8"))
        while True:
            if not self._socket.poll(int(self.timeout * 1000)):
                raise Error(f"{self.address}: no reply within {self.timeout:g} s "
                            "(is `rdsim serve` running there, and are the keys right?)")
            frames = self._socket.recv_multipart()
            reply = json.loads(frames[0])
            if reply.get("id") is None and "error" in reply:
                raise Error(f"{self.address}: {reply['error']}")
            if reply.get("id") == header["id"]:
                break  # else: the late reply of a request that timed out
        if "error" in reply:
            raise Error(f"{self.address}: {reply['error']}")
        arrays = {}
        for spec, frame in zip(reply.pop("arrays", []), frames[1:]):
            arrays[spec["name"]] = np.frombuffer(frame, dtype=_DTYPES[spec["dtype"]]).reshape(spec["shape"]).copy()
        return reply, arrays

    def _step_reply(self, header: dict):
        reply, arrays = self.request(header)
        info = dict(reply["info"])
        info.update({k: v for k, v in arrays.items() if k not in ("observation", "observation_vector")})
        if self.goal is not None:
            info["is_success"] = info["success"]
        return (self._observation(arrays), float(reply["reward"]), bool(reply["terminated"]),
                bool(reply["truncated"]), info)

    def _observation(self, arrays: dict):
        """A reply's observation: ``observation`` (the vector or image) and, for an image with the goal
        vector beside it, ``observation_vector`` (docs/protocol.md)."""
        flat = arrays["observation"]
        if "observation_vector" in arrays:
            vector = arrays["observation_vector"]
            flat = (flat, vector) if flat.dtype == np.uint8 else (None, np.concatenate([flat.ravel(), vector]))
        return flat if self.goal is None else goal_dict(self.goal, flat, copy=False, shape=self._image_shape)

    def _compute_reward(self, achieved_goal, desired_goal, info=None):
        """A goal env's reward for ``achieved_goal`` / ``desired_goal`` (last axis: the goal's points,
        3 values each), batched over the leading axes; what ``step`` returns (computed in this
        process, no request). ``info`` is accepted for Gymnasium-Robotics' signature and not read."""
        reward = _rdsim.compute_reward(self.goal, np.asarray(achieved_goal), np.asarray(desired_goal))
        return float(reward) if reward.ndim == 0 else reward

    # -- Gymnasium ------------------------------------------------------------------------------
    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        if options:
            raise Error(f"{self.address}: reset: options: rdsim envs take no reset options")
        super().reset(seed=seed)
        header: dict[str, Any] = {"request": "reset"}
        if seed is not None:
            header["seed"] = int(seed)
        _, arrays = self.request(header)
        return self._observation(arrays), {}

    def step(self, action):
        if isinstance(self.action_space, gymnasium.spaces.Discrete):
            if isinstance(action, (bool, np.bool_)) or not isinstance(action, (int, np.integer)) and not (
                    isinstance(action, np.ndarray) and action.ndim == 0 and action.dtype.kind in "iu"):
                raise Error(f"action: expected an integer in [0, {self.action_space.n - 1}], got {action!r}")
            payload: Any = int(action)
        else:
            a = np.asarray(action)
            if a.dtype.kind != "f" or a.shape != self.action_space.shape or not np.isfinite(a).all():
                raise Error(f"action: expected a finite float array of shape {self.action_space.shape}, got {a.dtype} {a.shape}")
            payload = [float(v) for v in a]
        return self._step_reply({"request": "step", "action": payload})

    def close(self) -> None:
        if getattr(self, "_socket", None) is None:
            return
        try:
            self.request({"request": "close"})
        except Error:
            pass
        self._socket.close()
        self._socket = None

    # -- robot control (robot envs) -------------------------------------------------------------
    def position(self, xyz):
        """The effector to the absolute point xyz (world frame, m) by IK: one env step, as step()."""
        return self._step_reply({"request": "position", "position": [float(v) for v in xyz]})

    def joints(self, targets):
        """Absolute targets for every joint (clamped to the limits): one env step, as step()."""
        return self._step_reply({"request": "joints", "joints": [float(v) for v in targets]})

    def cameras(self, width: int = 224, height: int = 224, names=None) -> dict:
        """{camera name: uint8 array (height, width, 3)} of the robot's cameras."""
        header: dict[str, Any] = {"request": "cameras", "width": int(width), "height": int(height)}
        if names is not None:
            header["cameras"] = list(names)
        return self.request(header)[1]

    def state(self) -> dict:
        """Joint positions, velocities and targets, effector pose, target and step count."""
        header, arrays = self.request({"request": "state"})
        return dict(arrays, steps=header["steps"])
