"""The package's ``rdsim`` command (rdsim/_cli.py): the rdsim binary the package carries."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys

import rdsim
import rdsim._cli as cli


def test_the_rdsim_command_runs_the_binary_the_package_carries(tmp_path):
    assert os.access(cli.binary_path(), os.X_OK), cli.binary_path()
    r = subprocess.run([sys.executable, "-m", "rdsim._cli", "--version"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == rdsim.__version__
    # The console script pip made beside the interpreter runs it too, with the arguments as given.
    script = shutil.which("rdsim", path=os.path.dirname(sys.executable))
    assert script is not None
    r = subprocess.run([script, "envs"], capture_output=True, text=True, timeout=60, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "jaka_button" in r.stdout


def test_a_package_without_its_binary_says_so(monkeypatch, capsys):
    monkeypatch.setattr(cli, "binary_path", lambda: "/nonexistent/rdsim")
    assert cli.main() == 1
    err = capsys.readouterr().err
    assert err.startswith("rdsim: this package has no rdsim binary (/nonexistent/rdsim)")
    assert len(err.strip().splitlines()) == 1
