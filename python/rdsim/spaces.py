"""Gymnasium spaces from an rdsim Spec (the dict the C++ module returns)."""
from __future__ import annotations

import numpy as np
from gymnasium import spaces


def observation_space(spec: dict) -> spaces.Space:
    """``Box`` float32 with the env's per-element bounds, or ``Box(0, 255)`` uint8 for images (H, W, C);
    for a goal env (``spec["goal"]``) a ``Dict`` of ``observation``, ``achieved_goal`` and
    ``desired_goal`` Boxes (Gymnasium-Robotics' GoalEnv layout), whose ``observation`` is the camera
    image when the env observes pixels."""
    shape = tuple(spec["observation_shape"])
    goal = spec.get("goal")
    if int(spec.get("observation_vector_size") or 0) > 0:  # an image with the goal vector beside it
        low = np.asarray(spec["observation_low"], dtype=np.float32)
        high = np.asarray(spec["observation_high"], dtype=np.float32)
        if spec["observation_dtype"] == "uint8":
            image = spaces.Box(low=0, high=255, shape=shape, dtype=np.uint8)
        else:
            size = int(np.prod(shape))
            image = spaces.Box(low=low[:size].reshape(shape), high=high[:size].reshape(shape), dtype=np.float32)
        boxes = {"observation": image}
        for key, part in goal_slices(goal).items():
            if key != "observation":
                boxes[key] = spaces.Box(low=low[part], high=high[part], dtype=np.float32)
        return spaces.Dict(boxes)
    if spec["observation_dtype"] == "uint8":
        return spaces.Box(low=0, high=255, shape=shape, dtype=np.uint8)
    low = np.asarray(spec["observation_low"], dtype=np.float32).reshape(shape)
    high = np.asarray(spec["observation_high"], dtype=np.float32).reshape(shape)
    if goal is None:
        return spaces.Box(low=low, high=high, shape=shape, dtype=np.float32)
    return spaces.Dict(
        {key: spaces.Box(low=low[part], high=high[part], dtype=np.float32) for key, part in goal_slices(goal).items()}
    )


def goal_slices(goal: dict) -> dict[str, slice]:
    """Where ``observation``, ``achieved_goal`` and ``desired_goal`` lie in a goal env's flat vector (for
    pixel observations: in its values, where ``observation`` is a Float32 image's values or empty)."""
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


def goal_dict(goal: dict, flat, copy: bool = True, shape: tuple = ()) -> dict[str, np.ndarray]:
    """A goal env's observation(s) as the Dict observation; views of ``flat`` unless ``copy``. ``flat`` is
    the flat vector(s) (last axis), or for pixel observations the pair (image bytes or None, values)
    that the C++ module returns, with ``shape`` the image's (H, W, C)."""
    if not isinstance(flat, tuple):
        return {key: (flat[..., part].copy() if copy else flat[..., part]) for key, part in goal_slices(goal).items()}
    pixels, values = flat
    if pixels is None:  # a Float32 image: the first values
        size = int(np.prod(shape))
        pixels = values[..., :size].reshape(values.shape[:-1] + tuple(shape))
    out = {"observation": pixels.copy() if copy else pixels}
    for key, part in goal_slices(goal).items():
        if key != "observation":
            out[key] = values[..., part].copy() if copy else values[..., part]
    return out


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
