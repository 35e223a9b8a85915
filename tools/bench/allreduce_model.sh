#!/usr/bin/env bash
# Paper model of data-parallel training's communication (not a measurement): ring allreduce of
# the gradients, as `mpirun -np P rdsim train` does once per minibatch (PPO/A2C) or gradient step
# (DQN). Per allreduce of n bytes over P ranks, every rank sends and receives 2 (P-1)/P n bytes in
# 2 (P-1) steps, each paying the link latency:
#     T(P) = 2 (P-1) alpha + 2 (P-1)/P n / bandwidth
#
#   tools/bench/allreduce_model.sh FLOATS CALLS_PER_UPDATE [COMPUTE_S_PER_UPDATE]
#     FLOATS   gradient floats per allreduce (= the network's parameters; `rdsim train` under
#              mpirun prints bytes and calls: bytes per call / 4)
#     CALLS    allreduces per update (PPO: n_epochs x minibatches per epoch)
#     COMPUTE  seconds one rank computes per update (rollout + training), for the efficiency column
#   BANDWIDTH_GBIT=10 ALPHA_US=25 RANKS="2 8 16 64" tools/bench/allreduce_model.sh 9671 80 0.15
set -euo pipefail
floats=${1:?usage: allreduce_model.sh FLOATS CALLS_PER_UPDATE [COMPUTE_S_PER_UPDATE]}
calls=${2:?usage: allreduce_model.sh FLOATS CALLS_PER_UPDATE [COMPUTE_S_PER_UPDATE]}
compute=${3:-0}
awk -v n="$floats" -v calls="$calls" -v compute="$compute" -v gbit="${BANDWIDTH_GBIT:-10}" \
    -v alpha_us="${ALPHA_US:-25}" -v ranks="${RANKS:-2 4 8 16 32 64}" 'BEGIN {
  bytes = 4 * n; bw = gbit * 1e9 / 8; alpha = alpha_us * 1e-6
  printf "ring allreduce of %d floats (%.1f kB), %d per update, %g Gb/s, latency %g us per step\n\n", n, bytes / 1e3, calls, gbit, alpha_us
  printf "| ranks | sent per rank per update | latency per update | transfer per update | allreduce per update |%s\n", (compute > 0 ? " compute share |" : "")
  printf "|---|---|---|---|---|%s\n", (compute > 0 ? "---|" : "")
  split(ranks, list, " ")
  for (k = 1; k in list; k++) {
    p = list[k]
    sent = calls * 2 * (p - 1) / p * bytes
    lat = calls * 2 * (p - 1) * alpha
    xfer = sent / bw
    t = lat + xfer
    printf "| %d | %.2f MB | %.1f ms | %.1f ms | %.1f ms |", p, sent / 1e6, 1e3 * lat, 1e3 * xfer, 1e3 * t
    if (compute > 0) printf " %.0f %% |", 100 * compute / (compute + t)
    printf "\n"
  }
}'
