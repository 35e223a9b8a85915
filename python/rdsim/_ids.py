"""Gymnasium ids of rdsim's envs (``rdsim/JakaButton-v0`` ...) and their registration."""
from __future__ import annotations

# Gymnasium id -> rdsim registry name. The classic-control envs carry Gymnasium's version of the
# same dynamics (CartPole-v1, Pendulum-v1); the robot tasks are version 0.
IDS: dict[str, str] = {
    "rdsim/JakaButton-v0": "jaka_button",
    "rdsim/JakaObstacle-v0": "jaka_obstacle",
    "rdsim/InMoovTomato-v0": "inmoov_tomato",
    "rdsim/Reach-v0": "reach",
    "rdsim/JakaReachGoal-v0": "reach_goal",
    "rdsim/JakaPush-v0": "push",
    "rdsim/JakaPickAndPlace-v0": "pick_and_place",
    "rdsim/JakaStack-v0": "stack",
    "rdsim/CartPole-v1": "cartpole",
    "rdsim/Pendulum-v1": "pendulum",
}


def env_name(env_id: str) -> str:
    """The registry name of ``env_id`` (a Gymnasium id or a registry name such as ``jaka_button``)."""
    from . import _rdsim

    if env_id in IDS:
        return IDS[env_id]
    if env_id in IDS.values():
        return env_id
    known = ", ".join(IDS)
    raise _rdsim.Error(f'unknown environment "{env_id}" (known: {known}; or a name from `rdsim envs`)')


def env_id(name: str) -> str:
    """The Gymnasium id of registry name ``name``."""
    for key, value in IDS.items():
        if value == name:
            return key
    return name


def register_envs() -> None:
    """Registers every id with Gymnasium (``gymnasium.make`` / ``gymnasium.make_vec``); idempotent."""
    import gymnasium

    for key in IDS:
        if key in gymnasium.registry:
            continue
        gymnasium.register(
            id=key,
            entry_point="rdsim.env:env_for_gymnasium",
            vector_entry_point="rdsim.vector:vector_env_for_gymnasium",
            kwargs={"env_id": key},
            # The C++ env truncates at its own max_steps: no TimeLimit wrapper on top.
            max_episode_steps=None,
            disable_env_checker=False,
        )
