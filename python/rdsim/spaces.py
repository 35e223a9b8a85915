"""Gymnasium spaces from an rdsim Spec (the dict the C++ module returns)."""
from __future__ import annotations

import numpy as np
from gymnasium import spaces


def observation_space(spec: dict) -> spaces.Space:
    """``Box`` float32 with the env's per-element bounds, or ``Box(0, 255)`` uint8 for images (H, W, C);
    for a goal env (``spec["goal"]``) a ``Dict`` of ``observation``, ``achieved_goal`` and
    ``desired_goal`` Boxes (Gymnasium-Robotics' GoalEnv layout)."""
    shape = tuple(spec["observation_shape"])
    if spec["observation_dtype"] == "uint8":
        return spaces.Box(low=0, high=255, shape=shape, dtype=np.uint8)
    low = np.asarray(spec["observation_low"], dtype=np.float32).reshape(shape)
    high = np.asarray(spec["observation_high"], dtype=np.float32).reshape(shape)
    goal = spec.get("goal")
    if goal is None:
        return spaces.Box(low=low, high=high, shape=shape, dtype=np.float32)
    return spaces.Dict(
        {key: spaces.Box(low=low[part], high=high[part], dtype=np.float32) for key, part in goal_slices(goal).items()}
    )


def goal_slices(goal: dict) -> dict[str, slice]:
    """Where ``observation``, ``achieved_goal`` and ``desired_goal`` lie in a goal env's flat vector."""
    n, size = int(goal["observation"]), 3 * int(goal["points"])
    return {
        "observation": slice(0, n),
        "achieved_goal": slice(n, n + size),
        "desired_goal": slice(n + size, n + 2 * size),
    }


def observation_parts(spec: dict) -> dict[str, slice]:
    """What each value of a vector observation is: part name -> its slice of the flat vector, in order
    (``{}`` when the env does not name them: images, classic control). A goal env's parts end with
    ``achieved_goal`` and ``desired_goal``; the others lie within its dict's ``observation`` at the
    same slices."""
    parts, at = {}, 0
    for name, size in spec.get("observation_parts") or []:
        parts[str(name)] = slice(at, at + int(size))
        at += int(size)
    return parts


def goal_dict(goal: dict, flat: np.ndarray, copy: bool = True) -> dict[str, np.ndarray]:
    """A goal env's flat observation(s) (last axis) as the Dict observation; views of ``flat`` unless ``copy``."""
    return {key: (flat[..., part].copy() if copy else flat[..., part]) for key, part in goal_slices(goal).items()}


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
