#!/usr/bin/env bash
# Builds the documentation site (mkdocs.yml, docs/) with `mkdocs build --strict` into build/site
# (or $RDSIM_BUILD_DIR/site): a broken link or anchor, or a page missing from the nav, fails.
# tools/test.sh runs it after the tests; `.venv/bin/mkdocs serve` shows the site while editing.
# Not `-q`: in mkdocs 1.6 `--strict -q` passes despite warnings, so the output is kept and shown
# when the build fails.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
site=$root/${RDSIM_BUILD_DIR:-build}/site
cd "$root"  # pymdownx.snippets reads CHANGELOG.md relative to the working directory
if ! log=$(NO_MKDOCS_2_WARNING=1 "$root/.venv/bin/mkdocs" build --strict -f "$root/mkdocs.yml" -d "$site" 2>&1); then
  echo "$log" >&2
  echo "tools/docs.sh: the documentation site does not build (mkdocs build --strict)" >&2
  exit 1
fi
echo "documentation site: $site"
