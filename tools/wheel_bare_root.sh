#!/usr/bin/env bash
# Proves the wheel on a bare system: a minimal Debian root made by debootstrap with only python3 and
# python3-venv, where an unprivileged user installs wheelhouse/rdsim-*.whl into a fresh venv and runs
# the package and the rdsim command (no compiler, no -dev package, no root for the install).
#
#   tools/build_wheel.sh && sudo tools/wheel_bare_root.sh
#
# Needs root (debootstrap, chroot, /proc inside the root) and Debian's debootstrap. The root is made
# once and kept as a tarball in build-bare/ (named after the suite and packages), so a second run
# costs seconds; the wheel's dependencies (NumPy, Gymnasium) are fetched on the host with pip and
# installed in the root from that folder. RDSIM_BARE_TIMESTEPS sets the training run's length.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
python=${RDSIM_PYTHON:-$root/.venv/bin/python}
suite=bookworm
packages=python3,python3-venv
mirror=${RDSIM_DEBIAN_MIRROR:-http://deb.debian.org/debian}
timesteps=${RDSIM_BARE_TIMESTEPS:-4096}
work=$root/build-bare
say() { echo "wheel_bare_root: $*"; }

[ "$(id -u)" -eq 0 ] || { echo "wheel_bare_root: needs root (debootstrap and chroot)" >&2; exit 1; }
command -v debootstrap >/dev/null || { echo "wheel_bare_root: needs debootstrap (apt install debootstrap)" >&2; exit 1; }
mapfile -t wheels < <(ls "$root"/wheelhouse/rdsim-*.whl 2>/dev/null)
[ ${#wheels[@]} -eq 1 ] || { echo "wheel_bare_root: expected one wheelhouse/rdsim-*.whl (tools/build_wheel.sh), found ${#wheels[@]}" >&2; exit 1; }
wheel=${wheels[0]}
start=$SECONDS

# The minimal root: made once, then unpacked fresh for every run.
mkdir -p "$work"
tarball=$work/debian-$suite-minbase-${packages//,/-}.tar
if [ ! -f "$tarball" ]; then
  say "making a minimal Debian $suite root with $packages (debootstrap from $mirror: a minute or more)"
  rm -rf "$work/make"
  debootstrap --variant=minbase --include="$packages" "$suite" "$work/make" "$mirror" >"$work/debootstrap.log" 2>&1 ||
    { tail -20 "$work/debootstrap.log" >&2; echo "wheel_bare_root: debootstrap failed (log: $work/debootstrap.log)" >&2; exit 1; }
  tar -C "$work/make" -cf "$tarball.tmp" . && mv "$tarball.tmp" "$tarball"
  rm -rf "$work/make"
fi
bare=$work/root
cleanup() { umount "$bare/proc" 2>/dev/null || true; }
trap cleanup EXIT
cleanup
rm -rf "$bare" && mkdir -p "$bare"
tar -C "$bare" -xf "$tarball"
say "root ready after $((SECONDS - start)) s"

# The proof that nothing else is there: no compiler, no headers, no X11.
for absent in usr/bin/gcc usr/bin/cc usr/bin/g++ usr/include/python3.11/Python.h usr/lib/x86_64-linux-gnu/libX11.so.6; do
  [ ! -e "$bare/$absent" ] || { echo "wheel_bare_root: the root is not bare: /$absent exists" >&2; exit 1; }
done

# The wheel and its dependencies (the Python of the root is Debian's 3.11, the wheel's).
mkdir -p "$bare/wheels"
"$python" -m pip download -q --disable-pip-version-check --only-binary :all: --python-version 3.11 \
  -d "$work/deps" -r <(grep -E '^(numpy|gymnasium)==' tools/requirements.txt)
cp "$work"/deps/*.whl "$wheel" "$bare/wheels/"
mount -t proc proc "$bare/proc"
# An unprivileged user (nobody) with a home folder does the install and the runs.
mkdir -p "$bare/home/user"
chown 65534:65534 "$bare/home/user"

chroot --userspec=65534:65534 "$bare" /usr/bin/env -i HOME=/home/user PATH=/usr/bin:/bin LANG=C.UTF-8 \
  RDSIM_BARE_TIMESTEPS="$timesteps" WHEEL="/wheels/$(basename "$wheel")" /bin/sh -eu -c '
cd "$HOME"
t0=$(date +%s)
python3 -m venv venv
venv/bin/pip install -q --disable-pip-version-check --no-index --find-links /wheels "$WHEEL"
echo "wheel_bare_root: installed in $(( $(date +%s) - t0 )) s (no compiler: $(command -v gcc cc || echo none))"
venv/bin/python - <<"PY"
import gymnasium, numpy as np, rdsim
env = gymnasium.make("rdsim/JakaButton-v0")
obs, _ = env.reset(seed=0)
for _ in range(200):
    obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
    if terminated or truncated:
        obs, _ = env.reset()
assert np.all(np.isfinite(obs)), obs
print("wheel_bare_root: import rdsim", rdsim.__version__, "and gymnasium.make(\"rdsim/JakaButton-v0\") stepped 200 times")
pixels = gymnasium.make("rdsim/JakaButton-v0", observation="raw_pixels", image_width=64, image_height=64)
image, _ = pixels.reset(seed=0)
assert image.shape == (64, 64, 3) and image.dtype == np.uint8, (image.shape, image.dtype)
assert image.std() > 5, "the 64x64 image is blank"
print("wheel_bare_root: a 64x64 pixel env renders (mean %.1f, std %.1f)" % (image.mean(), image.std()))
PY
export PATH="$HOME/venv/bin:$PATH"
rdsim train --config configs/jaka_button.json --timesteps "$RDSIM_BARE_TIMESTEPS" --quiet
test -s runs/jaka_button/model.bin
# The binary itself, not through the package: it finds the assets beside it (rdsim/data).
binary=$(venv/bin/python -c "import rdsim._cli; print(rdsim._cli.binary_path())")
"$binary" replay runs/jaka_button/model.bin --episodes 3
echo "wheel_bare_root: pip install to a trained model and its replay in $(( $(date +%s) - t0 )) s"
'
say "passed after $((SECONDS - start)) s"
