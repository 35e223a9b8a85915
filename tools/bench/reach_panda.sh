#!/usr/bin/env bash
# PPO on the `reach` task with pybullet_data's Franka Panda, a mesh robot as a user brings one:
# the URDF and its meshes are read from the installed pybullet package (never copied into the
# repository). Writes $OUT/reach_panda.json (configs/reach_jaka.json's PPO settings, the Panda's
# seven arm joints from its "ready" pose, the hand as effector, targets in a 30 x 60 x 20 cm box in
# front of it) and runs tools/bench/learning.sh on it: seeds 1 2 3, 1M steps, target 0.95 success
# over the last 100 episodes, then a deterministic replay of each final model.
#
#   OUT=/tmp/reach_panda tools/bench/reach_panda.sh
#
# Settings: OUT (default a new /tmp folder), SEEDS, TIMESTEPS (default 1000000), RDSIM_BIN, JOBS
# (as tools/bench/learning.sh takes them).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${OUT:-$(mktemp -d /tmp/rdsim_reach_panda.XXXXXX)}
mkdir -p "$out"
data=$("$root/.venv/bin/python" -c "import pybullet_data; print(pybullet_data.getDataPath())") || {
  echo "reach_panda: pybullet is not installed in $root/.venv (tools/setup.sh installs it)" >&2
  exit 1
}
"$root/.venv/bin/python" - "$root/configs/reach_jaka.json" "$data/franka_panda/panda.urdf" "$out/reach_panda.json" <<'PY'
import json, sys
config = json.load(open(sys.argv[1]))
config["env"].update({
    "urdf": sys.argv[2],
    "package_paths": [],
    "effector_link": "panda_hand",
    "joints": [f"panda_joint{i}" for i in range(1, 8)],
    "home_pose": [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785],  # rad: the Panda's "ready" pose
    "workspace_min": [0.2, -0.5, 0.02],  # m
    "workspace_max": [0.8, 0.5, 0.7],
    "target_centre": [0.5, 0.0, 0.25],
    "target_half_range": [0.15, 0.3, 0.1],
})
json.dump(config, open(sys.argv[3], "w"), indent=2)
PY
OUT="$out/runs" TIMESTEPS=${TIMESTEPS:-1000000} "$root/tools/bench/learning.sh" "$out/reach_panda.json" 0.95
