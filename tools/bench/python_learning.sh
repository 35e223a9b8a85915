#!/usr/bin/env bash
# Learning through the Python package (not a unit test; wall-clock): Stable-Baselines3 PPO and the
# CleanRL-style PPO (examples/) on rdsim/JakaButton-v0 through rdsim.make_vec, 8 envs, 300k steps,
# seeds 1 2 3: env steps and seconds until the success rate of the last 100 training episodes first
# reaches 0.95, and SB3's deterministic policy over 100 evaluation episodes.
#
#   tools/bench/python_learning.sh            (SEEDS="1 2 3" TIMESTEPS=300000)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
echo "cores: $(nproc)   load: $(cut -d' ' -f1-3 /proc/loadavg)"
for seed in ${SEEDS:-1 2 3}; do
  .venv/bin/python examples/sb3_ppo.py --seed "$seed" --timesteps "${TIMESTEPS:-300000}"
done
for seed in ${SEEDS:-1 2 3}; do
  .venv/bin/python examples/cleanrl_ppo.py --seed "$seed" --timesteps "${TIMESTEPS:-300000}"
done
