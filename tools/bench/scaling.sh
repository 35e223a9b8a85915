#!/usr/bin/env bash
# Scaling benchmark (not a unit test; rerun it on an idle machine, every figure is wall-clock):
#  1. `rdsim bench-fps --scaling` for jaka_button, ground truth and 64x64 pixels: total env steps/s
#     of a VecEnv on 1, 2, 4, ... threads up to every core, the speed-up over one thread, and the
#     pool's cost per env step against a plain loop, all in one run.
#  2. PPO on jaka_button (configs/jaka_button.json), seeds 1 2 3: wall-clock until the success rate
#     of the last 100 episodes first reaches 0.95, for
#       1 thread           one process, num_threads 1
#       2 threads          one process, num_threads 2 (bit-identical learning: only the clock differs)
#       mpirun -np 2       2 ranks x 1 thread, each with half the envs and half the minibatch, so the
#                          run is the same algorithm (8 envs, minibatches of 256) split over 2 processes
#     and the allreduce payload per update of the 2-rank runs (progress.csv, allreduce_bytes).
#
#   tools/bench/scaling.sh                  (RDSIM_BIN=build/rdsim SEEDS="1 2 3" OUT=/tmp/scaling)
#   MPIRUN_ARGS="--bind-to none" tools/bench/scaling.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${RDSIM_BIN:-build/rdsim}
seeds=${SEEDS:-1 2 3}
target=${TARGET:-0.95}
out=${OUT:-$(mktemp -d /tmp/rdsim_scaling.XXXXXX)}
mpirun=${MPIRUN:-mpirun}
# Open MPI refuses root unless told (CI, containers).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$root"
mkdir -p "$out"
echo "binary: $bin   output: $out   cores: $(nproc)   load: $(cut -d' ' -f1-3 /proc/loadavg)"

echo
echo "== 1. bench-fps --scaling (jaka_button)"
"$bin" bench-fps --scaling --env jaka_button --image-size 64 --json "$out/scaling.json"

# "steps wall" at the first episode whose last-100 success rate is >= target, or "never".
reached() {
  awk -F, -v t="$target" 'NR > 1 { s[n++ % 100] = $5
           if (n >= 100) { c = 0; for (i = 0; i < 100; i++) c += s[i]; if (c / 100 >= t) { print $2, $8; found = 1; exit } } }
       END { if (!found) print "never never" }' "$1"
}

half="$out/jaka_button_half.json"  # per-rank half of the shipped config, for 2 ranks
sed -e 's/"num_envs": 8/"num_envs": 4/' -e 's/"batch_size": 256/"batch_size": 128/' configs/jaka_button.json > "$half"
grep -q '"num_envs": 4' "$half" && grep -q '"batch_size": 128' "$half" || { echo "could not halve configs/jaka_button.json"; exit 1; }

echo
echo "== 2. PPO jaka_button: wall-clock to success >= $target over the last 100 episodes"
echo "| run | seed | steps to $target | wall-clock to $target (s) | whole run (s) | success, last 100 | allreduce bytes per update |"
echo "|---|---|---|---|---|---|---|"
for seed in $seeds; do
  for run in "1 thread" "2 threads" "mpirun -np 2"; do
    dir="$out/$(echo "$run" | tr ' ' '_')_seed$seed"
    start=$(date +%s%N)
    case "$run" in
      "1 thread")  "$bin" train --quiet --config configs/jaka_button.json --seed "$seed" --threads 1 --log-dir "$dir" ;;
      "2 threads") "$bin" train --quiet --config configs/jaka_button.json --seed "$seed" --threads 2 --log-dir "$dir" ;;
      *) "$mpirun" -np 2 ${MPIRUN_ARGS:-} "$bin" train --quiet --config "$half" --seed "$seed" --threads 1 --log-dir "$dir" ;;
    esac
    wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.1f", (b - a) / 1e9 }')
    read -r steps at < <(reached "$dir/episodes.csv")
    last=$(awk -F, 'NR > 1 { s[n++ % 100] = $5 } END { m = n < 100 ? n : 100; c = 0; for (i = 0; i < m; i++) c += s[i]; printf "%.2f", c / m }' "$dir/episodes.csv")
    bytes=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "allreduce_bytes") col = i } NR == 2 && col { print $col }' "$dir/progress.csv")
    printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$run" "$seed" "$steps" "$at" "$wall" "$last" "${bytes:--}"
  done
done
