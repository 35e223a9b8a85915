#!/usr/bin/env bash
# Builds rdsim if needed, runs the whole test suite, then builds the documentation site with
# `mkdocs build --strict` (a broken link or anchor, or a page missing from mkdocs.yml's nav, fails).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/tools/setup.sh"
cd "$root/${RDSIM_BUILD_DIR:-build}"
ctest --output-on-failure -j "$(nproc)" "$@"
# The site goes to the (git-ignored) build folder. Not `-q`: in mkdocs 1.6 `--strict -q` passes
# despite warnings, so the output is kept and shown when the build fails.
cd "$root"
if ! docs_log=$(NO_MKDOCS_2_WARNING=1 "$root/.venv/bin/mkdocs" build --strict -f "$root/mkdocs.yml" \
    -d "$root/${RDSIM_BUILD_DIR:-build}/site" 2>&1); then
  echo "$docs_log" >&2
  echo "tools/test.sh: the documentation site does not build (mkdocs build --strict)" >&2
  exit 1
fi
echo "documentation site: ${RDSIM_BUILD_DIR:-build}/site"
