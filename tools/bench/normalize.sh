#!/usr/bin/env bash
# normalize_observations against the shipped configs (issue #45; not a unit test): each config trained
# as shipped and with "normalize_observations": true, the same seeds, in one run on one machine,
# through tools/bench/learning.sh (its summary rows, and a deterministic replay of each final model).
#
#   tools/bench/normalize.sh                # jaka_button (PPO), pendulum_sac, cartpole_ppo; seeds 1 2 3
#   SEEDS="1 2 3 4 5" OUT=/tmp/norm JOBS=2 tools/bench/normalize.sh jaka_button
#
# Targets as docs/results.md judges them: jaka_button success 0.95 over 100 episodes; Pendulum mean return
# -200 over 10 episodes; CartPole mean return 475 over 100 episodes. The last lines compare the two
# variants of each config; the rows are in $OUT/<config>{,_normalized}/summary.csv.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${OUT:-$(mktemp -d /tmp/rdsim_normalize.XXXXXX)}
mkdir -p "$out/configs"
names=("$@")
[ ${#names[@]} -eq 0 ] && names=(jaka_button pendulum_sac cartpole_ppo)
py=${PYTHON:-python3}

for name in "${names[@]}"; do
  case "$name" in
    jaka_button) settings=(METRIC=success WINDOW=100); target=0.95 ;;
    pendulum_sac) settings=(METRIC=return WINDOW=10); target=-200 ;;
    cartpole_ppo) settings=(METRIC=return WINDOW=100); target=475 ;;
    *) echo "unknown config $name (jaka_button, pendulum_sac, cartpole_ppo)" >&2; exit 2 ;;
  esac
  # The variant: the shipped file with the key added (no paths in these configs to re-root).
  "$py" - "$root/configs/$name.json" "$out/configs/${name}_normalized.json" <<'PY'
import json, sys
config = json.load(open(sys.argv[1]))
config["normalize_observations"] = True
json.dump(config, open(sys.argv[2], "w"), indent=2)
PY
  for variant in "$name" "${name}_normalized"; do
    config="$root/configs/$name.json"
    [ "$variant" != "$name" ] && config="$out/configs/$variant.json"
    env "${settings[@]}" OUT="$out/$variant" "$root/tools/bench/learning.sh" "$config" "$target" | tee "$out/$variant.txt"
  done
done
echo "machine: $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores, $(date -u +%F)"
for name in "${names[@]}"; do
  for variant in "$name" "${name}_normalized"; do grep '^SUMMARY' "$out/$variant.txt"; done
done
