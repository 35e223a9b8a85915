#!/usr/bin/env bash
# The Python package's tests (tests/python) against the sanitizer build of rdsim._rdsim: the module of
# the clang AddressSanitizer + UndefinedBehaviorSanitizer build (build-fuzz/, configured with
# RDSIM_PYTHON=ON by .ci/run) with the package's Python files, imported by .venv's Python.
#
# Python itself is not instrumented, so the module cannot bring its own ASan runtime: clang's shared
# runtime (which also holds UBSan's and the coverage hooks' defaults) is preloaded into the
# interpreter. Leak checking is off: CPython, NumPy and torch keep memory until exit by design.
# The rdsim binary the tests start (RDSIM_BIN) is the same build's, for the tests that compare the
# module's numbers with the binary's (a clang build's floats differ from the Release build's in the
# last digits): a wrapper starts it without the preloaded runtime, since it has its own (static) one.
#
# Usage: tools/python_asan.sh [pytest arguments]   (RDSIM_FUZZ_BUILD_DIR, default build-fuzz)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RDSIM_FUZZ_BUILD_DIR:-$root/build-fuzz}
module=$(ls "$build"/python/_rdsim*.so 2>/dev/null | head -n 1 || true)
if [ -z "$module" ] || [ ! -x "$build/rdsim" ]; then
  echo "rdsim python-asan: no $build/python/_rdsim*.so or $build/rdsim: configure $build with -DRDSIM_PYTHON=ON and build it" >&2
  exit 1
fi
runtime=$(clang -print-file-name=libclang_rt.asan-x86_64.so)
[ -f "$runtime" ] || { echo "rdsim python-asan: clang's shared ASan runtime not found ($runtime)" >&2; exit 1; }

# The package as python/rdsim/ holds it, with the sanitizer module in place of the Release one.
package=$build/python-asan/rdsim
rm -rf "$build/python-asan"
mkdir -p "$package"
ln -s "$root"/python/rdsim/* "$package/"
ln -s "$module" "$package/"
mkdir -p "$build/python-asan/bin"
binary=$build/python-asan/bin/rdsim
printf '#!/bin/sh\nunset LD_PRELOAD\nexec "%s" "$@"\n' "$build/rdsim" > "$binary"
chmod +x "$binary"
# The package's `rdsim` command (rdsim/_cli.py) runs the binary it carries: the same wrapper.
mkdir -p "$package/bin"
ln -s "$binary" "$package/bin/rdsim"

cd "$root"
# ASan reports and UBSan's first finding end the process with an error: the test fails.
LD_PRELOAD=$runtime ASAN_OPTIONS=detect_leaks=0:allocator_may_return_null=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 PYTHONPATH="$build/python-asan" \
  RDSIM_BIN=$binary \
  "$root/.venv/bin/python" -m pytest -q -p no:cacheprovider tests/python "$@"
