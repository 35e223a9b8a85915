#!/usr/bin/env bash
# Learning from demonstrations, measured (not a unit test). Per env:
#   1. N scripted-expert episodes (rdsim demos record --expert --config configs/ENV.json, seeds 1000..);
#   2. behaviour cloning alone (configs/ENV_bc.json, seeds 1-3): success of a deterministic
#      `rdsim replay` over 100 episodes on unseen seeds (from reset(5000));
#   3. PPO from scratch (configs/ENV.json) and PPO warm-started from the same demonstrations
#      (configs/ENV_warm.json: the same PPO, plus the "demonstrations" object), seeds 1-3: the env steps
#      until the success rate over the last 100 training episodes first reaches TARGET, that rate and
#      the collision rate at the end of training, and a deterministic replay over 100 episodes.
# Demonstration steps are not env steps of the run; the summary lists them apart.
#
#   tools/bench/demos.sh [ENV ...]            (default: jaka_obstacle inmoov_tomato)
#   RDSIM_BIN=build/rdsim SEEDS="1 2 3" EPISODES=20 TARGET=0.90 OUT=/tmp/demos NICE=10 VARIANTS="bc scratch warm" \
#     tools/bench/demos.sh
# (Two invocations with the same OUT and different VARIANTS, e.g. "scratch" and "bc warm", can run side by
# side: they share summary.csv.)
# Writes $OUT/summary.csv (env, variant, seed, steps_to_target, final_success, final_collisions,
# replay_success, demo_steps, wall_s) and keeps every run folder (progress.csv, episodes.csv,
# pretrain.csv) under $OUT/ENV/.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${RDSIM_BIN:-build/rdsim}
seeds=${SEEDS:-1 2 3}
episodes=${EPISODES:-20}
target=${TARGET:-0.90}
niceness=${NICE:-10}
out=${OUT:-$(mktemp -d /tmp/rdsim_demos.XXXXXX)}
variants=${VARIANTS:-bc scratch warm}
envs=("$@")
[ ${#envs[@]} -gt 0 ] || envs=(jaka_obstacle inmoov_tomato)
cd "$root"
mkdir -p "$out"
summary="$out/summary.csv"
[ -f "$summary" ] || echo "env,variant,seed,steps_to_target,final_success,final_collisions,replay_success,demo_steps,wall_s" >"$summary"

# "reached_at final_success final_collisions" from episodes.csv: the first timestep at which the success
# rate over the last 100 episodes was >= target ("never" if not), and the success and collision rates of
# the last 100 episodes.
last100() {
  awk -F, -v t="$target" 'NR > 1 { k = n++ % 100; s[k] = $5; x[k] = $6
           if (n >= 100 && !hit) { c = 0; for (i = 0; i < 100; i++) c += s[i]; if (c / 100 >= t) hit = $2 } }
       END { m = (n < 100 ? n : 100); c = 0; h = 0; for (i = 0; i < m; i++) { c += s[i]; h += x[i] }
             printf "%s %.2f %.2f\n", (hit ? hit : "never"), (m ? c / m : 0), (m ? h / m : 0) }' "$1"
}

# A copy of a config reading its demonstrations from `demos`.
# (Written beside and renamed, so that side-by-side invocations never read a half-written file.)
with_demos() {
  sed "s|\"file\": \"[^\"]*\"|\"file\": \"$2\"|" "$1" >"$3.$$" && mv "$3.$$" "$3"
}

run() {  # env variant seed config
  local env=$1 variant=$2 seed=$3 config=$4 dir="$out/$1/$2_seed$3"
  local start wall reached final collisions replay
  start=$(date +%s%N)
  nice -n "$niceness" "$bin" train --quiet --overwrite --config "$config" --seed "$seed" --log-dir "$dir"
  wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.1f", (b - a) / 1e9 }')
  read -r reached final collisions < <(last100 "$dir/episodes.csv")
  replay=$(nice -n "$niceness" "$bin" replay "$dir/model.bin" -n 100 --seed 5000 | tail -n 1 | sed 's/.*success rate \([0-9.]*\).*/\1/')
  local used=$demo_steps
  [ "$variant" != scratch ] || used=0
  echo "$env,$variant,$seed,$reached,$final,$collisions,$replay,$used,$wall" >>"$summary"
  printf '%-14s %-8s seed %s: success >= %s first at %s steps; last 100: success %s, collisions %s; replay %s; %s s\n' \
    "$env" "$variant" "$seed" "$target" "$reached" "$final" "$collisions" "$replay" "$wall"
}

echo "binary: $bin   output: $out   seeds: $seeds   demonstrations: $episodes expert episodes   target: $target"
wants() { [[ " $variants " == *" $1 "* ]]; }
for env in "${envs[@]}"; do
  mkdir -p "$out/$env"
  demo_steps=0
  if wants bc || wants warm; then
    demos="$out/$env/$env.demo"
    rm -f "$demos.$$"
    "$bin" demos record --expert --config "configs/$env.json" -n "$episodes" --seed 1000 -q --out "$demos.$$"
    mv "$demos.$$" "$demos"
    demo_steps=$("$bin" demos info "$demos" | awk '/^steps/ { print $2 }')
    with_demos "configs/${env}_bc.json" "$demos" "$out/$env/bc.json"
    with_demos "configs/${env}_warm.json" "$demos" "$out/$env/warm.json"
  fi
  if wants bc; then
    for seed in $seeds; do run "$env" bc "$seed" "$out/$env/bc.json"; done
  fi
  for seed in $seeds; do
    if wants scratch; then run "$env" scratch "$seed" "configs/$env.json"; fi
    if wants warm; then run "$env" warm "$seed" "$out/$env/warm.json"; fi
  done
done
echo "summary: $summary"
column -s, -t "$summary"
