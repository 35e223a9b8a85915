#!/usr/bin/env bash
# Load test (not a unit test): a real `rdsim dashboard` and a real `rdsim serve`, each with 1000
# idle connections and 50 slow clients at once (and, for serve, a client that never reads 200
# camera replies), while a well-behaved client keeps asking for 20 s: its p99 latency, the
# server's peak resident memory, and a clean exit within a second of SIGINT/SIGTERM
# (tools/load_test.py; ctest runs a short version). Loopback only.
#
#   tools/bench/load.sh                    IDLE=2000 SLOW=100 HOLD_S=60 tools/bench/load.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=$(realpath "${RDSIM_BIN:-$root/build/rdsim}")
python=${RDSIM_PYTHON:-/usr/bin/python3}
cd "$root"
echo "binary: $bin   cores: $(nproc)   load: $(cut -d' ' -f1-3 /proc/loadavg)"
exec "$python" tools/load_test.py --rdsim "$bin" --idle "${IDLE:-1000}" --slow "${SLOW:-50}" \
  --seconds "${HOLD_S:-20}" --unread "${UNREAD:-200}" --max-rss-mb "${MAX_RSS_MB:-400}"
