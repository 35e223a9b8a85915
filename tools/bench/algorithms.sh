#!/usr/bin/env bash
# Every algorithm on jaka_button (not a unit test): trains configs/jaka_button*.json (one per
# algorithm) with seeds 1-3 through tools/bench/learning.sh, then writes
#   $OUT/<algorithm>/seed<k>/            one run folder per run (config.json names the algorithm,
#                                        as `rdsim plot` groups runs by it)
#   $OUT/jaka_button_algorithms.csv      every episode of every run: algorithm, seed, then the
#                                        columns of episodes.csv (the learning-curve figure's data)
#   $OUT/jaka_button_summary.csv         one row per run (learning.sh's summary.csv rows)
# and prints a Markdown table: success over the last 100 training episodes, the first timestep
# at which it reached 0.95, and a deterministic replay of the final model over 100 episodes.
#
#   tools/bench/algorithms.sh [algorithm...]     (default: all ten)
#   SEEDS="1 2 3" OUT=/tmp/algos JOBS=2 tools/bench/algorithms.sh sac ars
#   RESUME=1 OUT=/tmp/algos tools/bench/algorithms.sh    (keeps the runs already in /tmp/algos)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
export SEEDS=${SEEDS:-1 2 3}
out=${OUT:-$(mktemp -d /tmp/rdsim_algorithms.XXXXXX)}
algos=("$@")
[ ${#algos[@]} -eq 0 ] && algos=(ppo a2c dqn trpo sac td3 ddpg ars cma_es random)
mkdir -p "$out"

config_of() { if [ "$1" = ppo ]; then echo "$root/configs/jaka_button.json"; else echo "$root/configs/jaka_button_$1.json"; fi; }

for algo in "${algos[@]}"; do
  OUT="$out/$algo" METRIC=success WINDOW=100 "$root/tools/bench/learning.sh" "$(config_of "$algo")" 0.95
done

{
  echo "algorithm,seed,$(head -n 1 "$out/${algos[0]}/seed${SEEDS%% *}/episodes.csv")"
  for algo in "${algos[@]}"; do
    for seed in $SEEDS; do
      [ -f "$out/$algo/seed$seed/episodes.csv" ] && tail -n +2 "$out/$algo/seed$seed/episodes.csv" | sed "s/^/$algo,$seed,/"
    done
  done
} >"$out/jaka_button_algorithms.csv"
{
  echo "algorithm,$(head -n 1 "$out/${algos[0]}/summary.csv")"
  for algo in "${algos[@]}"; do tail -n +2 "$out/$algo/summary.csv" | sed "s/^/$algo,/"; done
} >"$out/jaka_button_summary.csv"

echo
echo "| algorithm | steps | success, last 100 episodes (seeds ${SEEDS// /, }) | success >= 0.95 first at | replay success (100 episodes) |"
echo "|---|---|---|---|---|"
awk -F, 'NR > 1 { a = $1; order[a] = order[a] ? order[a] : ++n; name[n] = a
                  steps[a] = $4; s[a] = s[a] (s[a] == "" ? "" : ", ") sprintf("%.2f", $13)
                  at[a] = at[a] (at[a] == "" ? "" : ", ") ($10 == "never" ? "never" : sprintf("%.1fk", $10 / 1000))
                  ev[a] = ev[a] (ev[a] == "" ? "" : ", ") sprintf("%.2f", $17) }
         END { for (i = 1; i <= n; i++) { a = name[i]; printf "| %s | %.0fk | %s | %s | %s |\n", a, steps[a] / 1000, s[a], at[a], ev[a] } }' \
  "$out/jaka_button_summary.csv"
echo
echo "episodes of every run: $out/jaka_button_algorithms.csv; one row per run: $out/jaka_button_summary.csv"
