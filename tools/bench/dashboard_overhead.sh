#!/usr/bin/env bash
# Benchmark (not a unit test): how much does serving the live dashboard slow training?
# Trains CONFIG with one seed REPEATS times without and REPEATS times with `--dashboard`
# (alternating, so drifts of the machine's load hit both alike); during the dashboard runs the page
# is open in headless Chromium (opened before the run starts), polling every 500 ms as a user's
# browser does. For each run it
# prints steps/s (timesteps / wall time of the last progress.csv row) and the CPU seconds of the
# rdsim process (user + system: the dashboard's threads included), then the medians, the median of
# the pairs' ratios, and (from one more run with the dashboard, sampled while it trains) how the
# CPU time splits between the training thread and the other threads. The timed runs are not sampled:
# reading every thread's /proc stat ten times a second slowed the runs with the dashboard's five
# extra threads more than those without (measured on the 2-core AMD VM: -1.3 % over 42 sampled pairs,
# +0.2 % paired over 16 unsampled ones).
#
# CLIENT=http replaces the browser by a small client making the page's requests at its rate (progress rows
# since the last answer every 500 ms, the list of runs every 5 s): the server's cost alone, without
# a browser competing for the same cores.
#
#   tools/bench/dashboard_overhead.sh [CONFIG]        (default: configs/jaka_button.json)
#   RDSIM_BIN=build/rdsim REPEATS=5 TIMESTEPS=300000 CLIENT=chromium|http tools/bench/dashboard_overhead.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${RDSIM_BIN:-build/rdsim}
config=${1:-configs/jaka_button.json}
repeats=${REPEATS:-5}
timesteps=${TIMESTEPS:-300000}
client=${CLIENT:-chromium}
chromium=${RDSIM_CHROMIUM:-/usr/bin/chromium}
out=${OUT:-$(mktemp -d /tmp/rdsim_dashboard_overhead.XXXXXX)}
mkdir -p "$out"
cd "$root"

ticks=$(getconf CLK_TCK)

# "steps/s cpu_s" of a finished run.
measure() {
  local sps cpu
  sps=$(tail -n 1 "$1/progress.csv" | awk -F, '{ printf "%.1f", $1 / $NF }')
  cpu=$(awk '{ printf "%.2f", $2 + $3 }' "$1.time")
  echo "$sps $cpu"
}

# Samples, every 0.1 s until the process ends, the CPU ticks (user + system) of its main thread
# (the training loop) and of all its other threads (the env worker pool when num_threads > 1, and the dashboard's server, if any): the last
# sample is the whole run's but for its last moments.
watch_threads() {
  local pid="" main other fields f
  for _ in $(seq 1000); do pid=$(pgrep -P "$1" || true); [ -n "$pid" ] && break; sleep 0.01; done
  echo "0 0" >"$2"
  [ -n "$pid" ] || return 0
  # Shell builtins only (one `sleep` per sample): a process started per thread and sample would
  # cost the run more with the dashboard's extra threads than without (measured: a `sed` per thread
  # every 0.1 s made the dashboard look 20 % slower on the 2-core VM).
  local line
  while kill -0 "$pid" 2>/dev/null; do
    main=0 other=0
    for f in /proc/"$pid"/task/*/stat; do
      read -r line 2>/dev/null <"$f" || continue
      read -r -a a <<<"${line##*) }"
      if [ "$f" = "/proc/$pid/task/$pid/stat" ]; then main=$((a[11] + a[12])); else other=$((other + a[11] + a[12])); fi
    done
    echo "$main $other" >"$2"
    sleep 0.1
  done
}

run_plain() {
  /usr/bin/time -f "%e %U %S" -o "$1.time" "$bin" train --quiet --config "$config" --seed 1 \
    --timesteps "$timesteps" --log-dir "$1" &
  local train=$!
  [ "${2:-}" = sampled ] && watch_threads "$train" "$1.threads"
  wait "$train"
}

# What the page does, over one kept-alive connection as a browser keeps it: the rows written since
# the last answer every 500 ms, the list of runs every 5 s, until the server goes away. (A curl
# process per request would measure process start-up instead: on the 2-core VM a curl loop aimed
# at a closed port, no server at all, already slowed training by 3-5 %.)
http_client() {
  python3 - "$1" "$2" <<'PY'
import http.client, json, sys, time
port = int(sys.argv[1])
open(sys.argv[2], "w").close()  # started: the interpreter's start-up is over
while True:
    try:
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
        conn.request("GET", "/api/runs")
        conn.getresponse().read()
        break
    except OSError:
        time.sleep(0.05)
next_offset, tick = 0, 0
while True:
    try:
        conn.request("GET", f"/api/progress?run=0:.&from={next_offset}")
        next_offset = json.loads(conn.getresponse().read()).get("next", next_offset)
        if tick % 10 == 0:
            conn.request("GET", "/api/runs")
            conn.getresponse().read()
    except (OSError, http.client.HTTPException, ValueError):
        break
    tick += 1
    time.sleep(0.5)
PY
}

# The browser is opened before training starts, on a page that waits for the dashboard and then
# loads it, so the run pays for an open page (polling, drawing), not for Chromium starting up.
run_with_dashboard() {
  local port=$((20000 + RANDOM % 20000)) profile train client_pid
  profile=$(mktemp -d /tmp/rdsim_overhead_profile.XXXXXX)
  if [ "$client" = http ]; then
    # Training starts once the client's Python is up (its start-up, ~50 ms of CPU, would otherwise
    # compete with the run's first second and be billed to the dashboard: measured -3 % at 300k
    # steps on the 2-core AMD VM, the training thread itself taking 5 % more CPU time).
    rm -f "$out/client_ready"
    http_client "$port" "$out/client_ready" &
    client_pid=$!
    for _ in $(seq 500); do [ -e "$out/client_ready" ] && break; sleep 0.01; done
  else
    cat >"$out/wait.html" <<HTML
<script>
const url = 'http://127.0.0.1:$port/';
(function poll() { fetch(url, {mode: 'no-cors'}).then(() => { location = url; }, () => setTimeout(poll, 50)); })();
</script>
HTML
    "$chromium" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking \
      --disable-component-update --disable-sync --user-data-dir="$profile" "file://$out/wait.html" >/dev/null 2>&1 &
    client_pid=$!
    sleep 5
  fi
  /usr/bin/time -f "%e %U %S" -o "$1.time" "$bin" train --quiet --config "$config" --seed 1 \
    --timesteps "$timesteps" --log-dir "$1" --dashboard "127.0.0.1:$port" &
  train=$!
  [ "${2:-}" = sampled ] && watch_threads "$train" "$1.threads"
  wait "$train"
  kill "$client_pid" 2>/dev/null || true
  wait "$client_pid" 2>/dev/null || true
  rm -rf "$profile"
}

echo "config: $config   timesteps: $timesteps   repeats: $repeats   client: $client   binary: $bin   output: $out"
without=() with=() cpu_without=() cpu_with=() ratios=()
for i in $(seq "$repeats"); do
  run_plain "$out/without_$i"
  read -r sps0 cpu < <(measure "$out/without_$i")
  without+=("$sps0") cpu_without+=("$cpu")
  echo "run $i without dashboard: $sps0 steps/s, $cpu CPU s"
  run_with_dashboard "$out/with_$i"
  read -r sps cpu < <(measure "$out/with_$i")
  with+=("$sps") cpu_with+=("$cpu")
  ratios+=("$(awk -v a="$sps0" -v b="$sps" 'BEGIN { printf "%.4f", b / a }')")
  echo "run $i with dashboard:    $sps steps/s, $cpu CPU s (pair ratio ${ratios[-1]})"
done
# One more run with the dashboard, its threads sampled (not timed: the sampling costs the run).
run_with_dashboard "$out/sampled" sampled
read -r main other <"$out/sampled.threads"
main=$(awk -v t="$ticks" -v v="$main" 'BEGIN { printf "%.3f", v / t }')
other=$(awk -v t="$ticks" -v v="$other" 'BEGIN { printf "%.3f", v / t }')
median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }
m0=$(median "${without[@]}") m1=$(median "${with[@]}") r=$(median "${ratios[@]}")
c0=$(median "${cpu_without[@]}") c1=$(median "${cpu_with[@]}")
awk -v a="$m0" -v b="$m1" -v c="$c0" -v d="$c1" -v r="$r" -v m="$main" -v o="$other" 'BEGIN {
  printf "median steps/s: %.1f without, %.1f with the dashboard and its client: %+.2f%%\n", a, b, (b / a - 1) * 100
  printf "median of the %s pairs'"'"' ratios (with / without): %.4f (%+.2f%%)\n", "'"$repeats"'", r, (r - 1) * 100
  printf "median CPU seconds of rdsim: %.2f without, %.2f with: %+.2f%%\n", c, d, (d / c - 1) * 100
  if (m > 0) printf "sampled run: training thread %.2f s, other threads (env workers, dashboard) %.2f s of CPU\n", m, o
  else print "sampled run: threads not sampled (the sampler did not find the process)" }'
