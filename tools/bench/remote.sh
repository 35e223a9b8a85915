#!/usr/bin/env bash
# Remote-control benchmark (issue #12; not a unit test), in one run on this machine:
#   1. `rdsim bench-remote`: jaka_button over loopback with CurveZMQ, one client: steps/s and
#      round-trip latency p50/p99 next to in-process steps/s; the same with 64x64 raw pixels;
#      4 clients at once against one;
#   2. tools/fuzz_remote.py: FUZZ_COUNT (default 10,000) hostile messages to a real `rdsim serve`,
#      then a well-behaved client, the server's memory, a clean exit;
#   3. with --learning: configs/jaka_button.json (300k steps, 8 envs) trained with a remote env and
#      with a local env, same seed: episodes.csv must be identical but for wall time, and the
#      success over the last 100 episodes is printed for both.
#
#   tools/bench/remote.sh [--learning] [--fuzz-only]
#   RDSIM_BIN=build-asan/rdsim tools/bench/remote.sh --fuzz-only     (the ASan/UBSan server run)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=$(realpath "${RDSIM_BIN:-$root/build/rdsim}")
python=${RDSIM_PYTHON:-/usr/bin/python3}
out=${OUT:-$(mktemp -d /tmp/rdsim_remote_bench.XXXXXX)}
mkdir -p "$out"
learning=0 fuzz_only=0
for arg in "$@"; do
  case $arg in
    --learning) learning=1 ;;
    --fuzz-only) fuzz_only=1 ;;
    *) echo "usage: tools/bench/remote.sh [--learning] [--fuzz-only]" >&2; exit 2 ;;
  esac
done
cd "$root"
echo "binary: $bin   output: $out   cores: $(nproc)   load: $(cut -d' ' -f1-3 /proc/loadavg)"

if [ "$fuzz_only" = 0 ]; then
  "$bin" bench-remote --env jaka_button --steps "${STEPS:-20000}" --runs "${RUNS:-3}" --clients 4 --image-size 64 \
    --json "$out/bench_remote.json"
fi

"$python" tools/fuzz_remote.py --rdsim "$bin" --count "${FUZZ_COUNT:-10000}"

if [ "$learning" = 1 ]; then
  keys="$out/keys"
  "$bin" keygen server --dir "$keys" >/dev/null
  "$bin" keygen trainer --dir "$out" >/dev/null
  mkdir -p "$keys/clients" && cp "$out/trainer.key" "$keys/clients/"
  "$bin" serve --keys "$keys" --bind 'tcp://127.0.0.1:*' >"$out/serve.out" 2>"$out/serve.log" &
  server=$!
  trap 'kill $server 2>/dev/null || true' EXIT
  for _ in $(seq 100); do grep -q "listening on" "$out/serve.out" 2>/dev/null && break; sleep 0.1; done
  address=$(grep -o 'tcp://[^ ]*' "$out/serve.out")
  "$python" - "$address" "$keys/server.key" "$out/trainer.key_secret" "$out/remote.json" <<'PY'
import json, sys
config = json.load(open("configs/jaka_button.json"))
config["env"].update(remote=sys.argv[1], server_key=sys.argv[2], client_key=sys.argv[3])
json.dump(config, open(sys.argv[4], "w"), indent=2)
PY
  for where in local remote; do
    config=configs/jaka_button.json
    [ "$where" = remote ] && config="$out/remote.json"
    start=$(date +%s%N)
    "$bin" train --quiet --config "$config" --log-dir "$out/$where"
    wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.1f", (b - a) / 1e9 }')
    rate=$(tail -n 100 "$out/$where/episodes.csv" | awk -F, '{ s += $5 } END { printf "%.2f", s / NR }')
    echo "$where env: $(tail -n 1 "$out/$where/progress.csv" | cut -d, -f1) steps in $wall s, success over the last 100 episodes $rate"
  done
  kill $server && wait $server || true
  if diff <(rev "$out/local/episodes.csv" | cut -d, -f2- | rev) <(rev "$out/remote/episodes.csv" | cut -d, -f2- | rev) >/dev/null; then
    echo "episodes.csv: identical but for wall time ($(($(wc -l <"$out/local/episodes.csv") - 1)) episodes)"
  else
    echo "episodes.csv: DIFFERENT"; exit 1
  fi
fi
