"""Shared settings of the rdsim Python tests (tools/test.sh runs them with the project's .venv)."""
import os
import pathlib
import sys
import tempfile

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "examples"))


def pytest_collection_modifyitems(config, items):
    # Long learning runs: only with RDSIM_SLOW=1 (never in CI, where CI=true).
    if os.environ.get("RDSIM_SLOW") == "1" and os.environ.get("CI", "").lower() != "true":
        return
    skip = pytest.mark.skip(reason="slow: set RDSIM_SLOW=1 to run (never in CI)")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)


@pytest.fixture(scope="session", autouse=True)
def sb3_log_folder():
    """Stable-Baselines3 makes a folder tempdir/SB3-<date-time> at every learn() without a logger:
    the session's SB3 runs (in this process and the examples it starts) share one, removed at the end."""
    with tempfile.TemporaryDirectory(prefix="rdsim_tests_sb3_") as folder:
        before = os.environ.get("SB3_LOGDIR")
        os.environ["SB3_LOGDIR"] = folder
        yield folder
        if before is None:
            del os.environ["SB3_LOGDIR"]
        else:
            os.environ["SB3_LOGDIR"] = before


def rdsim_binary() -> pathlib.Path:
    """The rdsim binary of this tree (RDSIM_BIN, else build/rdsim)."""
    return pathlib.Path(os.environ.get("RDSIM_BIN", ROOT / os.environ.get("RDSIM_BUILD_DIR", "build") / "rdsim"))


@pytest.fixture(scope="module")
def server():
    """`rdsim serve --insecure` on a free loopback port (tools/rdsim_client.py's ServerProcess),
    stopped (SIGTERM) after the module's tests."""
    pytest.importorskip("zmq")
    sys.path.insert(0, str(ROOT / "tools"))
    from rdsim_client import ServerProcess

    binary = rdsim_binary()
    if not binary.exists():
        pytest.fail(f"{binary} not found: build rdsim first (tools/setup.sh) or set RDSIM_BIN")
    with ServerProcess(str(binary)) as s:
        yield s
