#!/usr/bin/env bash
# Learning the goal-conditioned manipulation tasks (not a unit test): rdsim's SAC + hindsight
# experience replay, seeds 1-3, through tools/bench/learning.sh (target: 0.9 success over the last
# 100 training episodes; then a deterministic replay of each final model over 100 episodes).
#
#   tools/bench/her.sh [TASK...]      (default: push pick_and_place panda_push stack_demos stack_her)
#   OUT=/tmp/her SEEDS="1 2 3" JOBS=2 tools/bench/her.sh push compare
#
# Tasks:
#   push                   configs/jaka_push.json (JAKA + gripper, HER alone)
#   pick_and_place         configs/jaka_pick_and_place.json with 50 episodes of the scripted expert
#                          (recorded into $OUT/pick_and_place.demo)
#   pick_and_place_her     the same config without demonstrations (HER alone)
#   panda_push             configs/panda_push.json: jaka_push.json's settings with pybullet_data's
#                          Franka Panda by options (tools/setup.sh links pybullet's robots at
#                          .venv/pybullet_data; never copied)
#   stack_demos            configs/jaka_stack_demos.json with 50 episodes of the scripted expert
#                          (recorded into $OUT/stack.demo), target 0.6: stack_scatter's settings
#   stack_her              the same config without demonstrations (HER alone), target 0.6
#   stack_first            jaka_stack_demos.json's first settings, from which the variants below
#                          start: network.input_scale 5, no normalize_observations, no eval, and
#                          demonstrations with bc_epochs 200, demo_fraction 0.2, bc_weight 20 only
#   stack_starts           stack_first with half the training episodes starting from the
#                          demonstrations' states (demonstrations.start_fraction 0.5) and an
#                          evaluation of 50 episodes every 50k steps (eval.csv: the training
#                          window counts the episodes that start part-way)
#   stack_normalized       stack_starts with normalize_observations in place of network.input_scale
#   stack_demo_half        stack_normalized with demo_fraction 0.5 (half of every batch demonstrated)
#   stack_starts_most      stack_normalized with start_fraction 0.8
#   stack_half_most        stack_normalized with both (demo_fraction 0.5, start_fraction 0.8)
#   stack_partial          stack_half_most with the partial reward (env.reward_type "partial": -0.5
#                          while one cube is on its goal), its demonstrations recorded with it
#                          (into $OUT/stack_partial.demo)
#   stack_missed           stack_half_most with demonstrations of which half start with a missed
#                          grasp (demos record --missed-grasps 0.5 --only-successes, into
#                          $OUT/stack_missed.demo)
#   stack_missed_starts    stack_half_most with 50 expert episodes split in two: 25 plain ones
#                          (seeds 1025-1049, $OUT/stack_plain25.demo) fill the demonstration buffer
#                          and the cloning term, and they with 25 that start with a missed grasp
#                          (seeds 1000-1024, --missed-grasps 1) are the episodes' start states
#                          (demonstrations.start_file $OUT/stack_starts50.demo): the way back from a
#                          miss is met by RL, not cloned
#   stack_shift            stack_half_most with demonstrations.shift 0.05: each demonstrated
#                          transition drawn into a minibatch moved on the table by up to 5 cm in x
#                          and y, the whole scene together (against memorising the 50 layouts;
#                          docs/results.md: the gap to new layouts stays)
#   stack_redraw           stack_shift with demonstrations.start_redraw 1: every episode that starts
#                          from a demonstrated state gets a new layout for what the expert has not
#                          moved yet (the cubes still where the reset put them, the goal unless a
#                          cube is on it), so that the starts leave the 50 demonstrated layouts
#                          (docs/results.md: the gap to new layouts stays)
#   stack_scatter          stack_redraw with demonstrations.scatter 1 and scatter_goal: in every
#                          demonstrated transition drawn into a minibatch, the second cube gets a new
#                          place while the expert fetches and places the first, and the goal one
#                          while no cube has moved yet (what the expert's action there does not
#                          depend on); the same config as stack_demos
#   compare                rdsim's configs/jaka_push.json and Stable-Baselines3 2.9 SAC +
#                          HerReplayBuffer with the same settings (examples/sb3_her.py, torch on CPU)
#                          on rdsim/JakaPush-v0, seed by seed side by side, each pinned to one core
#                          (taskset; torch one thread): env steps and seconds to 0.9, final success.
#   compare_alone          the same pair one after the other, each with the whole machine: rdsim
#                          with RDSIM_GEMM=onednn on every core, SB3 with torch on every core.
#                          Both leave run folders (OUT/compare*/rdsim_seedN, sb3_seedN): `rdsim plot
#                          OUT/compare_alone --x wall_time -o F.png` draws success against seconds.
# Settings: OUT (default a new /tmp folder), SEEDS, JOBS, TIMESTEPS, RDSIM_BIN (as learning.sh),
# SB3_TIMESTEPS (compare: SB3's budget, default the config's total_timesteps), EDIT (stack_first,
# stack_normalized and the variants after it: a further Python edit of the config c, e.g.
# "c['demonstrations']['start_fraction'] = 0.95" or "c['sac']['gamma'] = 0.98").
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
out=${OUT:-$(mktemp -d /tmp/rdsim_her.XXXXXX)}
bin=${RDSIM_BIN:-build/rdsim}
seeds=${SEEDS:-1 2 3}
tasks=("$@")
[ ${#tasks[@]} -eq 0 ] && tasks=(push pick_and_place panda_push stack_demos stack_her)
mkdir -p "$out"
py="$root/.venv/bin/python"
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores; $(date -u +%F)"

# `config` with its JSON edited by the Python expression `edit` (c is the config) -> `path`.
edited_config() {
  "$py" - "$1" "$2" "$3" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
exec(sys.argv[2])
json.dump(c, open(sys.argv[3], "w"), indent=2)
PY
}

learn() {  # name config target
  OUT="$out/$1" METRIC=success WINDOW=100 "$root/tools/bench/learning.sh" "$2" "$3"
}

record_demos() {  # env: 50 episodes of the scripted expert -> $out/ENV.demo
  [ -f "$out/$1.demo" ] || "$bin" demos record --quiet --expert --env "$1" -n 50 --out "$out/$1.demo"
}

# "first_steps first_seconds final_success" of an episodes.csv: where the last 100 first reach 0.9.
first_at() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "success") s = i; if ($i == "wall_time") w = i } }
           NR > 1 { k = n++ % 100; v[k] = $s; sum += $s; if (n > 100) sum -= old[k]; old[k] = $s
                    if (n >= 100 && !hit && sum / 100 >= 0.9 - 1e-9) { hit = $2; at = $w } }
           END { c = 0; t = 0; for (i = 0; i < (n < 100 ? n : 100); i++) { t += v[i]; c++ }
                 printf "%s %s %.2f\n", (hit ? hit : "never"), (hit ? sprintf("%.0f", at) : "-"), (c ? t / c : 0) }' "$1"
}

sb3_budget() {  # SB3's env steps: SB3_TIMESTEPS, or the config's total_timesteps
  echo "${SB3_TIMESTEPS:-$("$py" -c "import json; print(json.load(open('configs/jaka_push.json'))['total_timesteps'])")}"
}

pair_header() {
  echo "| seed | rdsim: 0.9 at (steps, s) | rdsim final / eval | SB3: 0.9 at (steps, s) | SB3 final / eval |"
  echo "|---|---|---|---|---|"
}

pair_row() {  # seed rdsim_run sb3_run: the table row of one seed's pair (a replay of rdsim's model)
  local re se ra rs rf sa ss sf
  re=$("$bin" replay "$2/model.bin" -n 100 | tail -n 1 | sed -E 's/.*success rate ([0-9.]+) over.*/\1/')
  se=$(sed -E -n 's/.*over [0-9]+ episodes: success ([0-9.]+).*/\1/p' "$3.log")
  read -r ra rs rf < <(first_at "$2/episodes.csv")
  read -r sa ss sf < <(first_at "$3/episodes.csv")
  echo "| $1 | $ra, $rs | $rf / $re | $sa, $ss | $sf / $se |"
}

compare() {
  local sb3_steps
  sb3_steps=$(sb3_budget)
  mkdir -p "$out/compare"
  pair_header
  for seed in $seeds; do
    local r="$out/compare/rdsim_seed$seed" s="$out/compare/sb3_seed$seed"
    taskset -c 0 "$bin" train --quiet --overwrite --config configs/jaka_push.json --seed "$seed" --log-dir "$r" \
      >"$r.log" 2>&1 &
    taskset -c 1 "$py" examples/sb3_her.py --config configs/jaka_push.json --seed "$seed" --timesteps "$sb3_steps" \
      --torch-threads 1 --log-dir "$s" >"$s.log" 2>&1 &
    wait
    pair_row "$seed" "$r" "$s"
  done
}

# compare's pair, one run at a time on every core (the issue's "on 2 cores").
compare_alone() {
  local sb3_steps cores
  sb3_steps=$(sb3_budget)
  cores=$(nproc)
  mkdir -p "$out/compare_alone"
  pair_header
  for seed in $seeds; do
    local r="$out/compare_alone/rdsim_seed$seed" s="$out/compare_alone/sb3_seed$seed"
    RDSIM_GEMM=onednn "$bin" train --quiet --overwrite --config configs/jaka_push.json --seed "$seed" --log-dir "$r" \
      >"$r.log" 2>&1
    "$py" examples/sb3_her.py --config configs/jaka_push.json --seed "$seed" --timesteps "$sb3_steps" \
      --torch-threads "$cores" --log-dir "$s" >"$s.log" 2>&1
    pair_row "$seed" "$r" "$s"
  done
}

# The first settings of configs/jaka_stack_demos.json, and stack_normalized's edit of them (the
# demonstrations recorded into $out).
first="c['network']['input_scale'] = 5; c.pop('normalize_observations'); c.pop('eval'); c['demonstrations'] = {'file': '$out/stack.demo', 'bc_epochs': 200, 'demo_fraction': 0.2, 'bc_weight': 20}"
normalized="$first; c['demonstrations']['start_fraction'] = 0.5; c['eval'] = {'every': 100000, 'episodes': 50}; del c['network']['input_scale']; c['normalize_observations'] = True"

for task in "${tasks[@]}"; do
  case "$task" in
    push) learn push configs/jaka_push.json 0.9 ;;
    pick_and_place)
      record_demos pick_and_place
      edited_config configs/jaka_pick_and_place.json "c['demonstrations']['file'] = '$out/pick_and_place.demo'" \
        "$out/pick_and_place.json"
      learn pick_and_place "$out/pick_and_place.json" 0.9 ;;
    pick_and_place_her)
      edited_config configs/jaka_pick_and_place.json "del c['demonstrations']" "$out/pick_and_place_her.json"
      learn pick_and_place_her "$out/pick_and_place_her.json" 0.9 ;;
    panda_push) learn panda_push configs/panda_push.json 0.9 ;;
    stack_demos)
      record_demos stack
      edited_config configs/jaka_stack_demos.json "c['demonstrations']['file'] = '$out/stack.demo'" "$out/stack_demos.json"
      learn stack_demos "$out/stack_demos.json" 0.6 ;;
    stack_first)
      record_demos stack
      edited_config configs/jaka_stack_demos.json "$first${EDIT:+; $EDIT}" "$out/stack_first.json"
      learn stack_first "$out/stack_first.json" 0.6 ;;
    stack_starts)
      record_demos stack
      edited_config configs/jaka_stack_demos.json "$first; c['demonstrations']['start_fraction'] = 0.5; c['eval'] = {'every': 50000, 'episodes': 50}" \
        "$out/stack_starts.json"
      learn stack_starts "$out/stack_starts.json" 0.6 ;;
    stack_normalized)
      record_demos stack
      edited_config configs/jaka_stack_demos.json "$normalized${EDIT:+; $EDIT}" "$out/stack_normalized.json"
      learn stack_normalized "$out/stack_normalized.json" 0.6 ;;
    stack_demo_half|stack_starts_most|stack_half_most|stack_partial|stack_missed|stack_shift|stack_redraw|stack_scatter)
      # stack_normalized with half of every batch demonstrated (RLPD's symmetric sampling), with
      # four in five episodes started from the demonstrations' states, or with both (and the
      # partial reward).
      half="c['demonstrations']['demo_fraction'] = 0.5" most="c['demonstrations']['start_fraction'] = 0.8"
      case "$task" in
        stack_demo_half) edit="$normalized; $half" ;;
        stack_starts_most) edit="$normalized; $most" ;;
        stack_half_most) edit="$normalized; $half; $most" ;;
        stack_shift) edit="$normalized; $half; $most; c['demonstrations']['shift'] = 0.05" ;;
        stack_redraw) edit="$normalized; $half; $most; c['demonstrations'].update(shift=0.05, start_redraw=1.0)" ;;
        stack_scatter) edit="$normalized; $half; $most; c['demonstrations'].update(shift=0.05, start_redraw=1.0, scatter=1.0, scatter_goal=True)" ;;
        stack_missed) edit="$normalized; $half; $most; c['demonstrations']['file'] = '$out/stack_missed.demo'" ;;
        *) edit="$normalized; $half; $most; c['env']['reward_type'] = 'partial'; c['demonstrations']['file'] = '$out/stack_partial.demo'" ;;
      esac
      edited_config configs/jaka_stack_demos.json "$edit${EDIT:+; $EDIT}" "$out/$task.json"
      # The demonstrations' rewards are the config's env's (the partial reward's own for stack_partial).
      if [ "$task" = stack_partial ]; then
        [ -f "$out/stack_partial.demo" ] ||
          "$bin" demos record --quiet --expert --config "$out/$task.json" -n 50 --out "$out/stack_partial.demo"
      elif [ "$task" = stack_missed ]; then
        [ -f "$out/stack_missed.demo" ] ||
          "$bin" demos record --quiet --expert --env stack -n 50 --missed-grasps 0.5 --only-successes --out "$out/stack_missed.demo"
      else
        record_demos stack
      fi
      learn "$task" "$out/$task.json" 0.6 ;;
    stack_missed_starts)
      if [ ! -f "$out/stack_starts50.demo" ]; then
        "$bin" demos record --quiet --expert --env stack -n 25 --seed 1025 --only-successes --out "$out/stack_plain25.demo"
        cp "$out/stack_plain25.demo" "$out/stack_starts50.demo.part"
        "$bin" demos record --quiet --expert --env stack -n 25 --seed 1000 --missed-grasps 1 --only-successes --append \
          --out "$out/stack_starts50.demo.part"
        mv "$out/stack_starts50.demo.part" "$out/stack_starts50.demo"
      fi
      edited_config configs/jaka_stack_demos.json "$normalized; c['demonstrations'].update(demo_fraction=0.5, start_fraction=0.8, file='$out/stack_plain25.demo', start_file='$out/stack_starts50.demo')${EDIT:+; $EDIT}" \
        "$out/stack_missed_starts.json"
      learn stack_missed_starts "$out/stack_missed_starts.json" 0.6 ;;
    stack_her)
      edited_config configs/jaka_stack_demos.json "del c['demonstrations']" "$out/stack_her.json"
      learn stack_her "$out/stack_her.json" 0.6 ;;
    compare) compare ;;
    compare_alone) compare_alone ;;
    *) echo "her.sh: unknown task $task (push pick_and_place pick_and_place_her panda_push stack_demos stack_her stack_first stack_starts stack_normalized stack_demo_half stack_starts_most stack_half_most stack_partial stack_missed stack_missed_starts stack_shift stack_redraw stack_scatter compare compare_alone)" >&2
       exit 2 ;;
  esac
done
echo "runs: $out"
