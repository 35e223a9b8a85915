#!/usr/bin/env bash
# Benchmark (not a unit test): how much does serving the live dashboard slow training?
# Trains CONFIG with one seed REPEATS times without and REPEATS times with `--dashboard`
# (alternating, so drifts of the machine's load hit both alike); during the dashboard runs the page
# is open in headless Chromium, polling every 500 ms as a user's browser does. For each run it
# prints steps/s (timesteps / wall time of the last progress.csv row) and the CPU seconds of the
# rdsim process (user + system: the dashboard's threads included), then the medians and ratios.
#
#   tools/bench/dashboard_overhead.sh [CONFIG]        (default: configs/jaka_button.json)
#   RDSIM_BIN=build/rdsim REPEATS=5 TIMESTEPS=100000 tools/bench/dashboard_overhead.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${RDSIM_BIN:-build/rdsim}
config=${1:-configs/jaka_button.json}
repeats=${REPEATS:-5}
timesteps=${TIMESTEPS:-100000}
chromium=${RDSIM_CHROMIUM:-/usr/bin/chromium}
out=${OUT:-$(mktemp -d /tmp/rdsim_dashboard_overhead.XXXXXX)}
mkdir -p "$out"
cd "$root"

# "steps/s cpu_s" of a finished run.
measure() {
  local sps cpu
  sps=$(tail -n 1 "$1/progress.csv" | awk -F, '{ printf "%.1f", $1 / $NF }')
  cpu=$(awk '{ printf "%.2f", $2 + $3 }' "$1.time")
  echo "$sps $cpu"
}

run_plain() {
  /usr/bin/time -f "%e %U %S" -o "$1.time" "$bin" train --quiet --config "$config" --seed 1 \
    --timesteps "$timesteps" --log-dir "$1"
}

run_with_dashboard() {
  local port=$((20000 + RANDOM % 20000)) profile train browser
  profile=$(mktemp -d /tmp/rdsim_overhead_profile.XXXXXX)
  /usr/bin/time -f "%e %U %S" -o "$1.time" "$bin" train --quiet --config "$config" --seed 1 \
    --timesteps "$timesteps" --log-dir "$1" --dashboard "127.0.0.1:$port" &
  train=$!
  for _ in $(seq 200); do
    curl -s -o /dev/null "http://127.0.0.1:$port/api/runs" && break
    sleep 0.02
  done
  "$chromium" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking \
    --disable-component-update --disable-sync --user-data-dir="$profile" "http://127.0.0.1:$port/" >/dev/null 2>&1 &
  browser=$!
  wait "$train"
  kill "$browser" 2>/dev/null || true
  wait "$browser" 2>/dev/null || true
  rm -rf "$profile"
}

echo "config: $config   timesteps: $timesteps   repeats: $repeats   binary: $bin   output: $out"
without=() with=() cpu_without=() cpu_with=()
for i in $(seq "$repeats"); do
  run_plain "$out/without_$i"
  read -r sps cpu < <(measure "$out/without_$i")
  without+=("$sps") cpu_without+=("$cpu")
  echo "run $i without dashboard: $sps steps/s, $cpu CPU s"
  run_with_dashboard "$out/with_$i"
  read -r sps cpu < <(measure "$out/with_$i")
  with+=("$sps") cpu_with+=("$cpu")
  echo "run $i with dashboard:    $sps steps/s, $cpu CPU s"
done
median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }
m0=$(median "${without[@]}") m1=$(median "${with[@]}")
c0=$(median "${cpu_without[@]}") c1=$(median "${cpu_with[@]}")
awk -v a="$m0" -v b="$m1" -v c="$c0" -v d="$c1" 'BEGIN {
  printf "median steps/s: %.1f without, %.1f with the dashboard and its page open: %+.2f%%\n", a, b, (b / a - 1) * 100
  printf "median CPU seconds of rdsim: %.2f without, %.2f with: %+.2f%%\n", c, d, (d / c - 1) * 100 }'
