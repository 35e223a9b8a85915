#!/usr/bin/env bash
# Builds rdsim if needed and runs the whole test suite.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/tools/setup.sh"
cd "$root/${RDSIM_BUILD_DIR:-build}"
ctest --output-on-failure -j "$(nproc)" "$@"
