#!/usr/bin/env bash
# Installs the Debian packages rdsim needs (if missing), the project's Python environment (.venv)
# and builds rdsim into build/.
# Safe to run again: it only installs what is missing and rebuilds what changed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

mapfile -t wanted < <(grep -v -e '^#' -e '^[[:space:]]*$' tools/apt-packages.txt)
missing=()
for p in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "rdsim setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The project's Python environment (.venv): the Python package, its tests and the docs site. The
# pinned requirements are installed again only when tools/requirements.txt changes.
venv=$root/.venv
if [ ! -x "$venv/bin/python" ]; then
  echo "rdsim setup: creating $venv"
  python3 -m venv "$venv"
fi
stamp=$venv/.rdsim-requirements.sha256
wanted_sha=$(sha256sum tools/requirements.txt | cut -d' ' -f1)
if [ "$(cat "$stamp" 2>/dev/null)" != "$wanted_sha" ]; then
  echo "rdsim setup: installing tools/requirements.txt into $venv"
  "$venv/bin/pip" install -q --disable-pip-version-check -r tools/requirements.txt
  echo "$wanted_sha" > "$stamp"
fi
# pybullet's robot models (pybullet_data, a test-time reference, never copied into the repository)
# under one path that does not depend on the Python version: configs/reach_panda.json and
# configs/panda_push.json name ../.venv/pybullet_data/franka_panda/panda.urdf.
ln -sfn "$("$venv/bin/python" -c 'import pybullet_data; print(pybullet_data.getDataPath())')" "$venv/pybullet_data"

build_type=${RDSIM_BUILD_TYPE:-Release}
build_dir=${RDSIM_BUILD_DIR:-build}
# Built for this machine's CPU (-march=native) unless RDSIM_PORTABLE=1 asks for binaries that run
# on any CPU of the architecture (e.g. a cluster of mixed machines).
native=ON
[ "${RDSIM_PORTABLE:-0}" = "1" ] && native=OFF
# RDSIM_PYTHON=OFF: the C++ build never needs Python (the package's step below turns it on).
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="$build_type" -DRDSIM_NATIVE=$native -DRDSIM_PYTHON=OFF ${RDSIM_CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" -j "$(nproc)"

# The Python package (rdsim, python/) into .venv, built by scikit-build-core in the same build tree:
# the libraries are already built (position-independent), so only the extension module compiles.
# Offline-friendly: the build requirements and dependencies are tools/requirements.txt's.
echo "rdsim setup: installing the Python package into $venv"
CMAKE_BUILD_PARALLEL_LEVEL=$(nproc) "$venv/bin/pip" install -q --disable-pip-version-check --no-build-isolation \
  --no-deps -C build-dir="$build_dir" -C cmake.build-type="$build_type" "$root"
