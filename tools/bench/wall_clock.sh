#!/usr/bin/env bash
# Wall-clock and CPU time of whole training runs, back to back in one invocation so the figures
# are comparable (same machine, same load): each config is trained RUNS times (default 3, seed 1)
# and the median is printed. Not a unit test.
#
#   tools/bench/wall_clock.sh configs/cartpole_ppo.json configs/pendulum_sac.json
#   RUNS=5 RDSIM_BIN=build/rdsim tools/bench/wall_clock.sh configs/pendulum_sac.json
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${RDSIM_BIN:-build/rdsim}
runs=${RUNS:-3}
out=${OUT:-$(mktemp -d /tmp/rdsim_wall_clock.XXXXXX)}
[ $# -gt 0 ] || { echo "usage: tools/bench/wall_clock.sh CONFIG..." >&2; exit 2; }
mkdir -p "$out"
cd "$root"
echo "binary: $bin   $(nproc) cores   load average: $(cut -d' ' -f1-3 /proc/loadavg)   runs per config: $runs"
for config in "$@"; do
  name=$(basename "$config" .json)
  : >"$out/$name.times"
  for run in $(seq 1 "$runs"); do
    /usr/bin/time -f "%e %U" -o "$out/$name.time" \
      "$bin" train --quiet --config "$config" --seed 1 --log-dir "$out/${name}_run$run" >/dev/null
    cat "$out/$name.time" >>"$out/$name.times"
  done
  steps=$(tail -n 1 "$out/${name}_run1/progress.csv" | cut -d, -f1)
  sort -n "$out/$name.times" | awk -v n="$name" -v s="$steps" '{ w[NR] = $1; u[NR] = $2 }
    END { m = int((NR + 1) / 2); printf "%s: %s steps, median wall %.1f s (CPU %.1f s) over %d runs: %.0f steps/s\n", n, s, w[m], u[m], NR, s / w[m] }'
done
