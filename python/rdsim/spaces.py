"""Gymnasium spaces from an rdsim Spec (the dict the C++ module returns)."""
from __future__ import annotations

import numpy as np
from gymnasium import spaces


def observation_space(spec: dict) -> spaces.Box:
    """``Box`` float32 with the env's per-element bounds, or ``Box(0, 255)`` uint8 for images (H, W, C)."""
    shape = tuple(spec["observation_shape"])
    if spec["observation_dtype"] == "uint8":
        return spaces.Box(low=0, high=255, shape=shape, dtype=np.uint8)
    low = np.asarray(spec["observation_low"], dtype=np.float32).reshape(shape)
    high = np.asarray(spec["observation_high"], dtype=np.float32).reshape(shape)
    return spaces.Box(low=low, high=high, shape=shape, dtype=np.float32)


def action_space(spec: dict) -> spaces.Space:
    """``Discrete(n)`` or a float32 ``Box`` with the env's bounds."""
    if spec["discrete"]:
        return spaces.Discrete(int(spec["n"]))
    low = np.asarray(spec["action_low"], dtype=np.float32)
    high = np.asarray(spec["action_high"], dtype=np.float32)
    return spaces.Box(low=low, high=high, shape=low.shape, dtype=np.float32)


def render_fps(spec: dict) -> int:
    """Frames per second of real time: one frame per env step of ``control_dt`` simulated seconds."""
    dt = float(spec["control_dt"])
    return int(round(1.0 / dt)) if dt > 0 else 30
