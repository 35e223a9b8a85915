#!/usr/bin/env bash
# Learning benchmark for any training config (not a unit test): trains it with several seeds and
# reports, per run, what its episodes.csv shows and what a deterministic `rdsim replay` of the final
# model gives over EVAL_EPISODES episodes (as rl-baselines3-zoo evaluates). One summary row per seed
# goes to $OUT/summary.csv; the last line says how many seeds met the target.
#
#   tools/bench/learning.sh CONFIG [TARGET]
#
# METRIC=success (default): TARGET is a success rate (default 0.95) over the last WINDOW episodes.
# METRIC=return:            TARGET is a mean return (e.g. 475 for CartPole) over the last WINDOW episodes.
# A seed meets the target when the windowed value first reaches TARGET within BUDGET env steps
# (default: the whole run). WINDOW defaults to 100 episodes, the convention ("solved", SB3's
# ep_rew_mean). Other settings: SEEDS (default "1 2 3"), OUT (run folders, default a new /tmp
# folder), RDSIM_BIN (default build/rdsim), EVAL_EPISODES (default 100, 0 = no evaluation),
# JOBS (runs at a time, default 1; more makes the wall-clock column meaningless),
# TIMESTEPS (overrides the config's total_timesteps), THREADS (train's --threads), RESUME=1 (keep
# a seed whose summary row $OUT/seed<k>.row an earlier run of the same config left, instead of
# training it again).
#
#   SEEDS="$(seq -s' ' 1 10)" METRIC=return BUDGET=100000 tools/bench/learning.sh configs/cartpole_ppo.json 475
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${RDSIM_BIN:-build/rdsim}
seeds=${SEEDS:-1 2 3}
config=${1:?usage: tools/bench/learning.sh CONFIG [TARGET]}
metric=${METRIC:-success}
case "$metric" in
  success) target=${2:-0.95} ;;
  return) target=${2:?METRIC=return needs a TARGET return} ;;
  *) echo "METRIC must be success or return, got $metric" >&2; exit 2 ;;
esac
window=${WINDOW:-100}
budget=${BUDGET:-0}
eval_episodes=${EVAL_EPISODES:-100}
jobs=${JOBS:-1}
name=$(basename "$config" .json)
out=${OUT:-$(mktemp -d "/tmp/rdsim_learning_${name}.XXXXXX")}
mkdir -p "$out"

# "reached_at last_return last_success min_return episodes": over the last `window` episodes of an
# episodes.csv (columns episode, timesteps, return, length, success, ...): the first timestep at
# which the windowed mean of the metric reached the target ("never" if not), then at the end the
# mean return, success rate and lowest single return of the last `window` episodes.
window_stats() {
  awk -F, -v w="$window" -v t="$target" -v m="$metric" '
    NR > 1 { k = n++ % w; r[k] = $3; s[k] = $5; v = (m == "return" ? $3 : $5)
             sum += v; if (n > w) sum -= old[k]; old[k] = v
             if (n >= w && !hit && sum / w >= t - 1e-9) hit = $2 }
    END { c = (n < w ? n : w); q = 0; p = 0; lo = ""
          for (i = 0; i < c; i++) { q += r[i]; p += s[i]; if (lo == "" || r[i] + 0 < lo + 0) lo = r[i] }
          printf "%s %.2f %.3f %s %d\n", (hit ? hit : "never"), (c ? q / c : 0), (c ? p / c : 0), (lo == "" ? "nan" : lo), n }' "$1"
}

run_seed() {
  local seed=$1 dir="$out/seed$1" start wall steps at ret succ lo episodes eval_line eval_ret="" eval_succ="" met
  local extra=()
  if [ "${RESUME:-0}" = 1 ] && [ -f "$out/seed$seed.row" ]; then
    echo "seed $seed: kept from an earlier run ($out/seed$seed.row)"
    return 0
  fi
  [ -n "${TIMESTEPS:-}" ] && extra=(--timesteps "$TIMESTEPS")
  [ -n "${THREADS:-}" ] && extra+=(--threads "$THREADS")
  start=$(date +%s%N)
  if ! "$bin" train --quiet --overwrite --config "$config" --seed "$seed" --log-dir "$dir" "${extra[@]}" >"$out/seed$seed.log" 2>&1; then
    echo "seed $seed: training failed (see $out/seed$seed.log)"
    return 0
  fi
  wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.1f", (b - a) / 1e9 }')
  read -r at ret succ lo episodes < <(window_stats "$dir/episodes.csv")
  steps=$(tail -n 1 "$dir/progress.csv" | cut -d, -f1)
  if [ "$eval_episodes" -gt 0 ]; then
    # "mean return R, mean length L, success rate S over N episodes"
    eval_line=$("$bin" replay "$dir/model.bin" -n "$eval_episodes" | tail -n 1)
    eval_ret=$(echo "$eval_line" | sed -E 's/^mean return ([-0-9.naif]+),.*/\1/')
    eval_succ=$(echo "$eval_line" | sed -E 's/.*success rate ([-0-9.naif]+) over.*/\1/')
  fi
  met=no
  if [ "$at" != "never" ] && { [ "$budget" -eq 0 ] || [ "$at" -le "$budget" ]; }; then met=yes; fi
  printf 'seed %s: %s steps, %s episodes, %s s; last %s episodes: mean return %s, success %s, lowest return %s; %s >= %s first at %s steps (met: %s); eval (deterministic, %s episodes): return %s, success %s\n' \
    "$seed" "$steps" "$episodes" "$wall" "$window" "$ret" "$succ" "$lo" "$metric" "$target" "$at" "$met" \
    "$eval_episodes" "${eval_ret:--}" "${eval_succ:--}"
  echo "$name,$seed,$steps,$episodes,$wall,$window,$metric,$target,$at,$met,$ret,$succ,$lo,$eval_episodes,$eval_ret,$eval_succ" \
    >"$out/seed$seed.row"
}

cd "$root"
echo "config: $config   binary: $bin   output: $out   $metric target: $target over $window episodes" \
  "$( [ "$budget" -gt 0 ] && echo "within $budget steps")   jobs: $jobs   $(nproc) cores"
running=0
for seed in $seeds; do
  run_seed "$seed" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
done
wait
{
  echo "config,seed,steps,episodes,wall_s,window,metric,target,reached_at,met,last_mean_return,last_success,last_lowest_return,eval_episodes,eval_mean_return,eval_success"
  for seed in $seeds; do cat "$out/seed$seed.row" 2>/dev/null || true; done
} >"$out/summary.csv"
awk -F, 'NR > 1 { n++; met += ($10 == "yes"); if ($15 != "") { e++; es += $15; if (emin == "" || $15 + 0 < emin + 0) emin = $15; if (emax == "" || $15 + 0 > emax + 0) emax = $15 } }
         END { printf "SUMMARY %s: %d/%d seeds met the target; deterministic eval mean return %s (min %s, max %s) -> %s\n",
                      name, met, n, (e ? sprintf("%.1f", es / e) : "-"), (e ? emin : "-"), (e ? emax : "-"), FILENAME }' \
  name="$name" "$out/summary.csv"
