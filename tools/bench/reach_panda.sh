#!/usr/bin/env bash
# PPO on the `reach` task with pybullet_data's Franka Panda, a mesh robot as a user brings one:
# the URDF and its meshes are read from the installed pybullet package (never copied into the
# repository; tools/setup.sh links them at .venv/pybullet_data). Runs tools/bench/learning.sh on
# configs/reach_panda.json (configs/reach_jaka.json's PPO settings, the Panda's seven arm joints
# from its "ready" pose, the hand as effector, targets in a 30 x 60 x 20 cm box in front of it):
# seeds 1 2 3, 1M steps, target 0.95 success over the last 100 episodes, then a deterministic
# replay of each final model.
#
#   OUT=/tmp/reach_panda tools/bench/reach_panda.sh
#
# Settings: OUT (default a new /tmp folder), SEEDS, TIMESTEPS (default 1000000), RDSIM_BIN, JOBS
# (as tools/bench/learning.sh takes them).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${OUT:-$(mktemp -d /tmp/rdsim_reach_panda.XXXXXX)}
mkdir -p "$out"
[ -f "$root/.venv/pybullet_data/franka_panda/panda.urdf" ] || {
  echo "reach_panda: $root/.venv/pybullet_data is missing (tools/setup.sh links pybullet's robot models there)" >&2
  exit 1
}
OUT="$out/runs" TIMESTEPS=${TIMESTEPS:-1000000} "$root/tools/bench/learning.sh" "$root/configs/reach_panda.json" 0.95
