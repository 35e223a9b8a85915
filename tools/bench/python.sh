#!/usr/bin/env bash
# The Python package's speed (not a unit test; wall-clock, rerun on an idle machine): env steps/s of
#   rdsim.make_vec (8 envs, 1 and 2 threads; copies and copy=False) against the C++ VecEnv stepped
#   through the binding alone and `rdsim bench-fps` (no Python), against gymnasium.vector.SyncVectorEnv
#   of 8 rdsim.make envs, and on CartPole against envpool.make("CartPole-v1", env_type="gymnasium",
#   num_envs=8), Gymnasium's NumPy-vectorised CartPole and its SyncVectorEnv.
#
#   tools/bench/python.sh                         (RDSIM_BIN=build/rdsim, SECONDS_PER_ROW=3)
#   tools/bench/python.sh --env rdsim/CartPole-v1
#   tools/bench/python.sh --overhead              (only make_vec / C++ VecEnv, 8 and 64 envs, one thread,
#                                                  21 alternating rounds; about 2 minutes)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
RDSIM_BIN=${RDSIM_BIN:-build/rdsim} exec .venv/bin/python tools/bench/python_bench.py --seconds "${SECONDS_PER_ROW:-3}" "$@"
