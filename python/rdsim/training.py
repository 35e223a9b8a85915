"""``rdsim.train``: ``rdsim train`` in this process (the C++ ``Trainer``), with the CLI's output."""
from __future__ import annotations

import dataclasses
import json
import math
import numbers
import operator
import os
import sys
from typing import Any, Mapping, Optional, Union

from . import _rdsim

_WHERE = "rdsim.train"
# The keyword arguments of rdsim.train, the options of `rdsim train` (see train()'s docstring).
_ARGUMENTS = ("seed", "timesteps", "log_dir", "threads", "overwrite", "resume", "quiet", "max_memory", "dashboard")


@dataclasses.dataclass(frozen=True)
class TrainResult:
    """What a finished (or interrupted) run did; ``os.fspath(result)`` is its run folder."""

    run_dir: str  #: the run folder (progress.csv, episodes.csv, config.json, model.bin, checkpoint.bin)
    model_path: str  #: run_dir/model.bin
    checkpoint_path: str  #: run_dir/checkpoint.bin (``rdsim train --resume run_dir`` continues from it)
    timesteps: int  #: env steps of the run, including a resumed run's earlier ones
    total_timesteps: int  #: the run's target
    episodes: int  #: episodes finished
    updates: int  #: updates of the algorithm, including a resumed run's earlier ones
    window_episodes: int  #: episodes behind the statistics below (the last ``stats_window``)
    mean_return: float
    min_return: float
    max_return: float
    mean_length: float
    success_rate: float  #: fraction of the window's episodes that succeeded
    wall_time: float  #: seconds of env stepping and learning
    stop_signal: int  #: 2 (SIGINT) when a KeyboardInterrupt stopped the run; 0 when it ran to the end

    @property
    def interrupted(self) -> bool:
        """Whether a signal stopped the run before ``total_timesteps``."""
        return self.stop_signal != 0

    def __fspath__(self) -> str:
        return self.run_dir


def _error(message: str) -> Exception:
    return _rdsim.Error(f"{_WHERE}: {message}")


def _path(name: str, value: Any) -> str:
    if not isinstance(value, (str, os.PathLike)):
        raise _error(f"{name}: expected a path (str or os.PathLike), got a Python {type(value).__name__}")
    path = os.fspath(value)
    if not isinstance(path, str) or not path:
        raise _error(f"{name}: expected a non-empty path")
    return path


def _integer(name: str, value: Any) -> int:
    if isinstance(value, bool):
        raise _error(f"{name}: expected an integer, got a bool")
    try:
        return operator.index(value)  # Python and NumPy integers; not floats
    except TypeError:
        raise _error(f"{name}: expected an integer, got a Python {type(value).__name__}") from None


def _flag(name: str, value: Any) -> bool:
    if not isinstance(value, bool):
        raise _error(f"{name}: expected True or False, got a Python {type(value).__name__}")
    return value


def _config(config: Any) -> tuple[str, str]:
    """(path, JSON text): one of them empty."""
    if config is None:
        return "", ""
    if isinstance(config, Mapping):
        try:
            return "", json.dumps(dict(config), allow_nan=False)
        except (TypeError, ValueError) as e:
            raise _error(f"config: expected a dict of JSON values (str, numbers, bools, None, lists, dicts): {e}") from None
    return _path("config", config), ""


def train(config: Union[str, os.PathLike, Mapping[str, Any], None] = None, **overrides: Any) -> TrainResult:
    """Trains as ``rdsim train`` does, in this process; returns the :class:`TrainResult`.

    ``config`` is a config file (``configs/*.json``) or the same as a dict; ``None`` with
    ``resume=``. The keyword arguments are the command's options:

    - ``seed`` (int), ``timesteps`` (int), ``log_dir`` (path): replace the config's ``seed``,
      ``total_timesteps`` and ``log_dir``, checked by the config reader's rules;
    - ``threads`` (int in [1, 4096]): the config's ``num_threads``;
    - ``overwrite=True``: a new run may replace another run's files in its folder;
    - ``resume`` (path): continue the run in this folder from its checkpoint (no ``config``);
    - ``quiet=True``: no progress line (the summary line stays, as with ``rdsim train -q``);
    - ``max_memory`` (GB): the limit for the run's estimated memory (default 80% of the machine's);
    - ``dashboard`` ("HOST:PORT"): serve the run's live dashboard while training.

    The progress line and the summary go to the process's stderr and stdout (file descriptors 2 and
    1, as the binary writes them). The GIL is released while the trainer works; Python's signal
    handlers run between updates. Ctrl-C (``KeyboardInterrupt``, or any exception a signal handler
    raises) stops the run as it stops ``rdsim train``: the update in progress finishes,
    checkpoint.bin and model.bin are saved, the message saying how to resume is printed, and then
    the exception is raised again, with the stopped run's :class:`TrainResult` as its ``result``
    attribute. Bad arguments, configs and run folders raise :class:`rdsim.Error` with the CLI's
    one-line message.
    """
    unknown = sorted(set(overrides) - set(_ARGUMENTS))
    if unknown:
        raise _error(f"unknown argument {unknown[0]!r}: expected one of {', '.join(_ARGUMENTS)}")
    config_path, config_json = _config(config)
    settings: list[tuple[str, str, str]] = []  # TrainerSettings::overrides: (option, config key, text)
    for name, key in (("seed", "seed"), ("timesteps", "total_timesteps")):
        if overrides.get(name) is not None:
            settings.append((f"{_WHERE}({name}=...)", key, str(_integer(name, overrides[name]))))
    if overrides.get("log_dir") is not None:
        settings.append((f"{_WHERE}(log_dir=...)", "log_dir", _path("log_dir", overrides["log_dir"])))
    threads = overrides.get("threads")
    if threads is not None:
        threads = _integer("threads", threads)
        if not 1 <= threads <= 4096:
            raise _error(f"threads: expected an integer in [1, 4096], got {threads}")
    max_memory = overrides.get("max_memory")
    if max_memory is not None:
        if isinstance(max_memory, bool) or not isinstance(max_memory, numbers.Real):
            raise _error(f"max_memory: expected a number of GB in [0.001, 1e6], got a Python {type(max_memory).__name__}")
        max_memory = float(max_memory)
        if not (math.isfinite(max_memory) and 0.001 <= max_memory <= 1e6):
            raise _error(f"max_memory: expected a number of GB in [0.001, 1e6], got {max_memory:g}")
    resume = overrides.get("resume")
    resume = "" if resume is None else _path("resume", resume)
    dashboard = overrides.get("dashboard")
    if dashboard is not None and not isinstance(dashboard, str):
        raise _error(f"dashboard: expected \"HOST:PORT\", got a Python {type(dashboard).__name__}")
    overwrite = _flag("overwrite", overrides.get("overwrite", False))
    quiet = _flag("quiet", overrides.get("quiet", False))

    # Python's buffered output first, so that it comes before the trainer's (C stdio, fd 1 and 2).
    for stream in (sys.stdout, sys.stderr):
        if stream is not None:
            stream.flush()
    result, interruption = _rdsim.train(config_path, config_json, resume, settings, threads, overwrite, max_memory, quiet,
                                        dashboard or "")
    outcome = TrainResult(**result)
    if interruption is not None:
        interruption.result = outcome
        raise interruption
    return outcome
