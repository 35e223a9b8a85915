#!/usr/bin/env bash
# CartPole learning benchmark (not a unit test): trains each algorithm's shipped config with 10
# seeds (tools/bench/learning.sh) and reports, per run, the first timestep at which the mean return
# of the last 100 episodes reaches 475 ("solved", the conventional window), the last 100 episodes'
# mean and lowest return, and a deterministic evaluation of the final policy over 100 episodes.
# Targets (published baselines): PPO, DQN, TRPO solved within 100k steps, A2C within 500k.
#
#   tools/bench/cartpole_learning.sh [algorithm...]     (default: ppo a2c dqn trpo ars cma_es)
#   SEEDS="1 2 3" OUT=/tmp/cartpole_bench JOBS=2 tools/bench/cartpole_learning.sh dqn
# Run folders and summary.csv files: $OUT/<algorithm>/.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
export SEEDS=${SEEDS:-1 2 3 4 5 6 7 8 9 10}
out=${OUT:-$(mktemp -d /tmp/rdsim_cartpole_bench.XXXXXX)}
algos=("$@")
[ ${#algos[@]} -eq 0 ] && algos=(ppo a2c dqn trpo ars cma_es)
declare -A budget=([ppo]=100000 [a2c]=500000 [dqn]=100000 [trpo]=100000 [ars]=0 [cma_es]=0)

for algo in "${algos[@]}"; do
  OUT="$out/$algo" METRIC=return WINDOW=100 BUDGET="${budget[$algo]:-0}" \
    "$root/tools/bench/learning.sh" "$root/configs/cartpole_${algo}.json" 475
done
