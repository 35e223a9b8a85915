"""rdsim from Python: every rdsim env in-process with the Gymnasium API.

- :func:`make` -- one env as a ``gymnasium.Env``; with ``remote="tcp://host:port"`` a :class:`RemoteEnv`.
- :func:`make_vec` -- the C++ vector env as a ``gymnasium.vector.VectorEnv`` (zero-copy batches,
  GIL released while stepping, ``step_async``/``step_wait``).
- :func:`load_model` -- a policy saved by ``rdsim train``.
- :func:`train` -- ``rdsim train`` in this process (the C++ trainer), returning a :class:`TrainResult`.
- :class:`RemoteEnv` -- an env served by ``rdsim serve`` (needs pyzmq).
- :class:`Error` -- every bad input (an option, an action, a call after ``close()``) raises it,
  with the CLI's one-line message.

Importing the package registers the ids (``rdsim/JakaButton-v0``, ``rdsim/JakaObstacle-v0``,
``rdsim/InMoovTomato-v0``, ``rdsim/Reach-v0``, ``rdsim/CartPole-v1``, ``rdsim/Pendulum-v1``) with Gymnasium.
"""
from __future__ import annotations

import os as _os

# The envs load their URDFs from $RDSIM_ROOT/assets, by default the source tree the module was built
# from; an installed package that outlived that tree uses the copy installed beside it.
from . import _rdsim

if not _os.environ.get("RDSIM_ROOT") and not _os.path.isdir(_os.path.join(_rdsim.source_dir, "assets")):
    _packaged = _os.path.join(_os.path.dirname(__file__), "data")
    if _os.path.isdir(_os.path.join(_packaged, "assets")):
        _os.environ["RDSIM_ROOT"] = _packaged

from ._ids import IDS, register_envs
from ._rdsim import Error, env_seed
from .env import RdsimEnv, make
from .model import Model, load_model
from .training import TrainResult, train
from .vector import RdsimVectorEnv, make_vec

__version__: str = _rdsim.__version__

__all__ = [
    "Error",
    "IDS",
    "Model",
    "RdsimEnv",
    "RdsimVectorEnv",
    "RemoteEnv",
    "TrainResult",
    "env_seed",
    "envs",
    "load_model",
    "make",
    "make_vec",
    "register_envs",
    "train",
]


def envs() -> list[dict]:
    """Every registered env: id, name, description, whether it has cameras (``supports_pixels``: its
    agent may observe camera images, ``observation="raw_pixels"``, and it draws frames,
    ``render_mode="rgb_array"``), and its default options."""
    import json

    from ._ids import env_id

    return [
        {"id": env_id(name), "name": name, "description": description, "supports_pixels": pixels,
         "defaults": json.loads(defaults)}
        for name, description, pixels, defaults in _rdsim.registry()
    ]


def __getattr__(name: str):
    # RemoteEnv needs pyzmq, an optional dependency: imported on first use.
    if name == "RemoteEnv":
        from .remote import RemoteEnv

        return RemoteEnv
    raise AttributeError(f"module 'rdsim' has no attribute {name!r}")


register_envs()
