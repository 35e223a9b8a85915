#!/usr/bin/env bash
# Pendulum learning benchmark (not a unit test): trains the continuous-action algorithms' shipped
# configs with 10 seeds (tools/bench/learning.sh) and reports, per run, the first timestep at
# which the mean return of the last 10 episodes reaches -200 (rl-baselines3-zoo's figure is about
# -150 at 20k steps for SAC and TD3), the last 10 episodes' mean and lowest return, and a
# deterministic evaluation of the final policy over 100 episodes.
# Targets: SAC and TD3 within 20k steps, DDPG within 50k.
#
#   tools/bench/pendulum_learning.sh [algorithm...]     (default: sac td3 ddpg)
#   SEEDS="1 2 3" OUT=/tmp/pendulum_bench JOBS=2 tools/bench/pendulum_learning.sh sac
# Run folders and summary.csv files: $OUT/<algorithm>/.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
export SEEDS=${SEEDS:-1 2 3 4 5 6 7 8 9 10}
out=${OUT:-$(mktemp -d /tmp/rdsim_pendulum_bench.XXXXXX)}
algos=("$@")
[ ${#algos[@]} -eq 0 ] && algos=(sac td3 ddpg)
declare -A budget=([sac]=20000 [td3]=20000 [ddpg]=50000)

for algo in "${algos[@]}"; do
  OUT="$out/$algo" METRIC=return WINDOW=10 BUDGET="${budget[$algo]:-0}" \
    "$root/tools/bench/learning.sh" "$root/configs/pendulum_${algo}.json" -200
done
