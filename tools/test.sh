#!/usr/bin/env bash
# Builds rdsim if needed, runs the whole test suite, then builds the documentation site
# (tools/docs.sh: `mkdocs build --strict`, so a broken link or a page missing from the nav fails).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/tools/setup.sh"
cd "$root/${RDSIM_BUILD_DIR:-build}"
ctest --output-on-failure -j "$(nproc)" "$@"
"$root/tools/docs.sh"
