#!/usr/bin/env bash
# Learning benchmark for any training config (not a unit test): trains it with several seeds and
# reports, per run, the success rate, mean return and collision rate of the last 100 episodes (from
# episodes.csv), the first timestep at which that success rate reached the target, the wall-clock
# time, and what a deterministic `rdsim replay` of the saved model gives over 100 episodes.
#
#   tools/bench/learning.sh CONFIG [TARGET]       (TARGET: success rate, default 0.95)
#   RDSIM_BIN=build/rdsim SEEDS="1 2 3" OUT=/tmp/learn tools/bench/learning.sh configs/jaka_button.json
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${RDSIM_BIN:-build/rdsim}
seeds=${SEEDS:-1 2 3}
config=${1:?usage: tools/bench/learning.sh CONFIG [TARGET]}
target=${2:-0.95}
name=$(basename "$config" .json)
out=${OUT:-$(mktemp -d "/tmp/rdsim_learning_${name}.XXXXXX")}

# "rate return collisions first_collisions reached_at": success rate, mean return and collision rate
# of the last 100 episodes, the collision rate of the first 100, and the first timestep at which the
# success rate over the last 100 episodes was >= target ("never" if not).
last100() {
  awk -F, -v t="$target" 'NR > 1 { k = n++ % 100; s[k] = $5; r[k] = $3; x[k] = $6; ts = $2
           if (n <= 100) first += $6
           if (n >= 100 && !hit) { c = 0; for (i = 0; i < 100; i++) c += s[i]; if (c / 100 >= t) { hit = ts } } }
       END { m = (n < 100 ? n : 100); c = 0; q = 0; h = 0
             for (i = 0; i < m; i++) { c += s[i]; q += r[i]; h += x[i] }
             printf "%.2f %.2f %.2f %.2f %s\n", (m ? c / m : 0), (m ? q / m : 0), (m ? h / m : 0), (m ? first / m : 0),
                    (hit ? hit : "never") }' "$1"
}

cd "$root"
echo "config: $config   binary: $bin   output: $out   target success: $target"
for seed in $seeds; do
  dir="$out/seed$seed"
  start=$(date +%s%N)
  if ! "$bin" train --quiet --overwrite --config "$config" --seed "$seed" --log-dir "$dir"; then
    echo "seed $seed: training failed"
    continue
  fi
  wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.1f", (b - a) / 1e9 }')
  read -r rate ret hits first_hits at < <(last100 "$dir/episodes.csv")
  steps=$(tail -n 1 "$dir/progress.csv" | cut -d, -f1)
  replay=$("$bin" replay "$dir/model.bin" -n 100 | tail -n 1)
  printf 'seed %s: %s steps in %s s; last 100 episodes: success %s, mean return %s, collisions %s (first 100: %s); success >= %s first at %s steps\n' \
    "$seed" "$steps" "$wall" "$rate" "$ret" "$hits" "$first_hits" "$target" "$at"
  printf '        replay (deterministic): %s\n' "$replay"
done
