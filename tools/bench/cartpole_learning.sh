#!/usr/bin/env bash
# CartPole learning benchmark (not a unit test): trains each algorithm with several seeds and
# reports, per run, the first timestep at which the mean return of the last 20 finished episodes
# (episodes.csv) reaches 475, and the wall-clock time of the whole run.
# Targets: PPO <= 100k steps, A2C <= 500k, DQN <= 100k, in 3 of 3 seeds.
#
#   tools/bench/cartpole_learning.sh [algorithm...]     (default: ppo a2c dqn)
#   RDSIM_BIN=build/rdsim SEEDS="1 2 3" OUT=/tmp/cartpole_bench tools/bench/cartpole_learning.sh ppo
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${RDSIM_BIN:-build/rdsim}
seeds=${SEEDS:-1 2 3}
out=${OUT:-$(mktemp -d /tmp/rdsim_cartpole_bench.XXXXXX)}
algos=("$@")
[ ${#algos[@]} -eq 0 ] && algos=(ppo a2c dqn)
declare -A target=([ppo]=100000 [a2c]=500000 [dqn]=100000)

# First timestep at which the mean of the last 20 episode returns is >= 475, or "not reached".
solved_at() {
  awk -F, 'NR > 1 { r[n++ % 20] = $3; if (n >= 20) { s = 0; for (i = 0; i < 20; i++) s += r[i];
             if (s / 20 >= 475) { print $2; found = 1; exit } } }
           END { if (!found) print "not reached" }' "$1"
}

cd "$root"
echo "binary: $bin   output: $out   $(nproc) cores"
for algo in "${algos[@]}"; do
  config="configs/cartpole_${algo}.json"
  ok=0; runs=0; steps_sum=0; wall_sum=0
  for seed in $seeds; do
    dir="$out/${algo}_seed${seed}"
    start=$(date +%s%N)
    if ! "$bin" train --quiet --overwrite --config "$config" --seed "$seed" --log-dir "$dir"; then
      echo "$algo seed $seed: training failed"
      runs=$((runs + 1))
      continue
    fi
    wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.1f", (b - a) / 1e9 }')
    at=$(solved_at "$dir/episodes.csv")
    runs=$((runs + 1))
    wall_sum=$(awk -v a="$wall_sum" -v b="$wall" 'BEGIN { print a + b }')
    if [ "$at" != "not reached" ] && [ "$at" -le "${target[$algo]}" ]; then
      ok=$((ok + 1)); steps_sum=$((steps_sum + at))
    fi
    printf '%s seed %s: mean(last 20) >= 475 at %s steps; wall %.1f s\n' "$algo" "$seed" "$at" "$wall"
  done
  mean_steps="-"
  [ $ok -gt 0 ] && mean_steps=$((steps_sum / ok))
  printf 'SUMMARY %s: %d/%d seeds reached 475 within %d steps (mean %s steps); mean wall %.1f s per run\n' \
    "$algo" "$ok" "$runs" "${target[$algo]}" "$mean_steps" "$(awk -v s="$wall_sum" -v n="$runs" 'BEGIN { print (n > 0 ? s / n : 0) }')"
done
