#!/usr/bin/env bash
# Builds rdsim if needed, runs the whole test suite (C++ with ctest, then Python with pytest), then
# builds the documentation site
# (tools/docs.sh: `mkdocs build --strict`, so a broken link or a page missing from the nav fails).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/tools/setup.sh"
build_dir=$root/${RDSIM_BUILD_DIR:-build}
cd "$build_dir"
ctest --output-on-failure -j "$(nproc)" "$@"

# The Python package's tests (tests/python, pytest in .venv; the long learning runs are marked slow
# and skipped). pytest's exit code 5 means it collected no tests: a broken suite, so a failure too.
cd "$root"
status=0
RDSIM_BIN=$build_dir/rdsim "$root/.venv/bin/python" -m pytest -q -o cache_dir="$build_dir/pytest_cache" tests/python || status=$?
if [ "$status" -eq 5 ]; then
  echo "rdsim test: pytest collected no Python tests (tests/python): the suite is broken" >&2
fi
[ "$status" -eq 0 ] || exit "$status"

"$root/tools/docs.sh"
