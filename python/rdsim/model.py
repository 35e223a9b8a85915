"""``rdsim.load_model``: a policy saved by ``rdsim train`` (model.bin or checkpoint.bin)."""
from __future__ import annotations

import json
import os
from collections.abc import Mapping
from typing import Any, Union

import numpy as np

from . import _rdsim
from .spaces import action_space, goal_slices, observation_space


class Model:
    """A saved policy, loaded and checked as ``rdsim replay`` loads it.

    ``predict(observations, deterministic=True)`` takes a batch ``(n, *observation shape)`` (or one
    observation) and returns ``n`` actions: an int64 array for Discrete envs, a float32 array
    ``(n, dim)`` for Box envs (one action for one observation). A goal env's model also takes its
    ``Dict`` observations (``observation``, ``achieved_goal``, ``desired_goal``: what ``rdsim.make``
    and ``rdsim.make_vec`` return) as well as the flat vectors. ``deterministic=False`` samples from
    the policy with the model's own generator (seeded from the config's seed).
    """

    def __init__(self, path: Union[str, os.PathLike]) -> None:
        self.path = os.fspath(path)
        self._model = _rdsim.Model(self.path)
        #: The resolved training config the model was trained with (a dict, as ``config.json``).
        self.config: dict[str, Any] = json.loads(self._model.config_json)
        #: The algorithm's name ("ppo", "dqn", ...).
        self.algorithm: str = self._model.algorithm
        spec = self._model.spec
        self._goal = spec.get("goal")
        self.observation_space = observation_space(spec)
        self.action_space = action_space(spec)

    def predict(self, observations: np.ndarray, deterministic: bool = True) -> Union[np.ndarray, int]:
        """Actions for a batch of observations (see the class docstring)."""
        if isinstance(observations, Mapping):
            observations = self._flat(observations)
        return self._model.predict(observations, bool(deterministic))

    def _flat(self, observations: Mapping) -> np.ndarray:
        """A goal env's Dict observation(s) as the flat vector(s) the policy reads."""
        if self._goal is None:
            raise _rdsim.Error(f"{self.path}: predict: a dict of observations is for goal envs; "
                               f"{self.config.get('env', {}).get('name', '?')} observes arrays")
        slices = goal_slices(self._goal)
        if set(observations) != set(slices):
            raise _rdsim.Error(f"{self.path}: predict: expected a dict of {', '.join(slices)}, got keys "
                               f"{', '.join(map(str, observations))}")
        parts = {key: np.asarray(observations[key], dtype=np.float32) for key in slices}
        batch = parts["observation"].shape[:-1]
        flat = np.empty(batch + (max(s.stop for s in slices.values()),), np.float32)
        for key, part in slices.items():
            if parts[key].shape != batch + (part.stop - part.start,):
                raise _rdsim.Error(f"{self.path}: predict: {key} of shape {parts[key].shape}, expected "
                                   f"{batch + (part.stop - part.start,)}")
            flat[..., part] = parts[key]
        return flat

    def export_onnx(self, path: Union[str, os.PathLike]) -> int:
        """Writes the deterministic policy as an ONNX model (``rdsim export MODEL --onnx PATH``): input
        ``"observation"`` (float32, ``(batch, size)``), output ``"action"`` (int64 ``(batch,)`` for
        Discrete envs, float32 ``(batch, dim)`` for Box ones). Checked against :meth:`predict` before it
        is written; returns the file's size in bytes. :class:`rdsim.Error` for the random agent's model
        (it has no policy). Pixel policies take uint8 ``(batch, height, width, channels)``."""
        return self._model.export_onnx(os.fspath(path))

    def __repr__(self) -> str:
        return f"<rdsim.Model {self.algorithm} on {self.config.get('env', {}).get('name', '?')} from {self.path}>"


def load_model(path: Union[str, os.PathLike]) -> Model:
    """Loads ``path`` (a model.bin or checkpoint.bin); :class:`rdsim.Error` for a damaged or foreign file."""
    return Model(path)
