#!/usr/bin/env bash
# Runs rdsim's libFuzzer targets (tests/fuzz/) for as long as asked.
#   tools/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]      targets: config urdf model request demos mesh policy (default: all)
# Builds build-fuzz/ with clang, ASan+UBSan and libFuzzer (RDSIM_FUZZ) if needed. Each target
# starts from its seed corpus (tests/fuzz/corpus/<target>, copied to build-fuzz/corpus/<target>,
# which keeps what the fuzzer adds) and writes crashes to build-fuzz/findings/<target>/.
# A finding is fixed, then its input goes to tests/fuzz/regressions/<target>/ (run by ctest).
# Prints executions per second and total executions per target; exit 1 on a finding.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(config urdf model request demos mesh policy)
build=${RDSIM_FUZZ_BUILD_DIR:-$root/build-fuzz}

if [ ! -x "$build/fuzz_model" ] || [ -n "${RDSIM_FUZZ_REBUILD:-}" ]; then
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRDSIM_FUZZ=ON >/dev/null
fi
cmake --build "$build" -j "$(nproc)" --target fuzz_config fuzz_urdf fuzz_model fuzz_request fuzz_demos fuzz_mesh fuzz_policy rdsim >/dev/null

export RDSIM_ROOT="$root"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
status=0
for t in "${targets[@]}"; do
  corpus="$build/corpus/$t"
  findings="$build/findings/$t"
  mkdir -p "$corpus" "$findings"
  cp -n "$root/tests/fuzz/corpus/$t/"* "$corpus/" 2>/dev/null || true
  log="$build/fuzz_$t.log"
  # -rss_limit_mb / -malloc_limit_mb: a single input may not use more than 2 GB (none should come close).
  if ! "$build/fuzz_$t" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="$findings/" "$corpus" \
      "$root/tests/fuzz/regressions/$t" >"$log" 2>&1; then
    status=1
    echo "fuzz $t: FINDING (see $log and $findings/)"
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  speed=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1)
  echo "fuzz $t: ${runs:-?} executions in ${seconds} s, ${speed:-?} exec/s, ${cov:-cov: ?}, corpus $(ls "$corpus" | wc -l) inputs"
done
exit $status
