"""The ``rdsim`` command of an installed package: runs the rdsim binary the wheel carries
(``rdsim/bin/rdsim``), the same program as a source build's ``build/rdsim``."""
from __future__ import annotations

import os
import sys


def binary_path() -> str:
    """Where the package's rdsim binary lies (it may be missing from a package built without it)."""
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "bin", "rdsim")


def main() -> int:
    exe = binary_path()
    if not os.access(exe, os.X_OK):
        print(f"rdsim: this package has no rdsim binary ({exe}); reinstall it (pip install rdsim) "
              "or build from source (README)", file=sys.stderr)
        return 1
    # Importing the package (above, through rdsim/__init__) set RDSIM_ROOT to the installed assets
    # and configs where the source tree it was built from is gone; the binary inherits it.
    os.execv(exe, ["rdsim", *sys.argv[1:]])
    return 1  # not reached: execv replaces this process or raises OSError


if __name__ == "__main__":
    sys.exit(main())
