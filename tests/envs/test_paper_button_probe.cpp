// A measurement, not a check (hidden tag, ctest does not run it): how close scripted controllers
// with privileged state get to the button on the paper preset configs/paper/jaka_button.json,
// i.e. whether "within 2.5 cm at step 1000" is reachable with the six far-target moves at all.
// Run: build/test_envs "[.paper_probe]"   (about a minute; issue #17, README "Paper presets")
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "env_test_util.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/rng.hpp"

using namespace rdsim;
using namespace rdsim::test;

namespace {

// The action whose `repeat` copies, tried on the real simulator from the current state (saved
// and restored), end closest to the button.
Action lookahead_action(Env& env, EnvState& state, int repeat) {
  const std::string start = state.save_state();
  float best = 1e9f;
  int best_action = 0;
  for (int a = 0; a < 6; ++a) {
    state.load_state(start, "probe");
    StepResult r;
    for (int k = 0; k < repeat; ++k) r = env.step(Action::discrete(a));
    if (r.info.distance < best) best = r.info.distance, best_action = a;
  }
  state.load_state(start, "probe");
  return Action::discrete(best_action);
}

// One controller over `episodes` preset episodes (targets by seeds 100...): successes, mean final
// distance (m). repeat 0: move along the largest component of target - effector; else lookahead.
void measure(const char* name, int repeat, int episodes) {
  auto env = make_env(paper_env_config("jaka_button"));
  auto* state = dynamic_cast<EnvState*>(env.get());
  REQUIRE(state);
  int successes = 0;
  double final_sum = 0.0;
  for (int ep = 0; ep < episodes; ++ep) {
    Observation o = env->reset(100 + ep);
    StepResult r;
    for (bool done = false; !done;) {
      // The preset's observation is effector - target (3 floats).
      r = env->step(repeat == 0 ? greedy_action(-to_target(o)) : lookahead_action(*env, *state, repeat));
      o = r.observation;
      done = r.terminated || r.truncated;
    }
    successes += r.info.success ? 1 : 0;
    final_sum += r.info.distance;
  }
  std::printf("%s: success %d/%d, mean distance at the last step %.3f m\n", name, successes, episodes,
              final_sum / episodes);
}

}  // namespace

TEST_CASE("paper jaka_button probe: scripted controllers near the button", "[.paper_probe]") {
  measure("axis greedy", 0, 20);
  measure("1-step lookahead", 1, 20);
  measure("10-step lookahead", 10, 6);
}

TEST_CASE("paper jaka_button probe: opposite moves alternated do not cancel", "[.paper_probe]") {
  // There is no no-op: hovering means alternating moves. From the rest pose, 100 steps of each
  // opposite pair; the net displacement (m) is how far such a "hold" drifts.
  auto env = make_env(paper_env_config("jaka_button"));
  Observation o = env->reset(100);
  for (int pair = 0; pair < 3; ++pair) {
    const Eigen::Vector3f start = o.values.head<3>();
    for (int t = 0; t < 100; ++t) o = env->step(Action::discrete(2 * pair + t % 2)).observation;
    const Eigen::Vector3f net = o.values.head<3>() - start;
    std::printf("actions %d/%d alternated 100 steps: net (%.3f, %.3f, %.3f), %.3f m\n", 2 * pair, 2 * pair + 1,
                net.x(), net.y(), net.z(), net.norm());
  }
}

TEST_CASE("paper jaka_button probe: how far one move carries the effector", "[.paper_probe]") {
  // From states along random-action episodes (every 25th step of 1000, targets by seeds 100-109),
  // each of the six moves is tried (state saved and restored): how far the effector goes in one
  // env step, the shortest of the six, and how close to the button the best move ends.
  auto env = make_env(paper_env_config("jaka_button"));
  auto* state = dynamic_cast<EnvState*>(env.get());
  REQUIRE(state);
  std::vector<float> shortest, longest, best_after, now;
  Rng rng(7);
  for (int ep = 0; ep < 10; ++ep) {
    Observation o = env->reset(100 + ep);
    for (int t = 0; t < 1000; ++t) {
      if (t % 25 == 24) {
        const std::string start = state->save_state();
        const Eigen::Vector3f offset = -to_target(o);  // target - effector
        float lo = 1e9f, hi = 0.0f, best = 1e9f;
        for (int a = 0; a < 6; ++a) {
          state->load_state(start, "probe");
          const StepResult r = env->step(Action::discrete(a));
          const float moved = (-to_target(r.observation) - offset).norm();  // the target does not move
          lo = std::min(lo, moved), hi = std::max(hi, moved), best = std::min(best, r.info.distance);
        }
        state->load_state(start, "probe");
        shortest.push_back(lo), longest.push_back(hi), best_after.push_back(best), now.push_back(offset.norm());
      }
      const StepResult r = env->step(Action::discrete(static_cast<int>(rng.next_u64() % 6)));
      o = r.observation;
      if (r.terminated || r.truncated) break;
    }
  }
  auto quartiles = [](std::vector<float> v) {
    std::sort(v.begin(), v.end());
    return Eigen::Vector3f(v[v.size() / 4], v[v.size() / 2], v[3 * v.size() / 4]);
  };
  const Eigen::Vector3f s = quartiles(shortest), l = quartiles(longest), d = quartiles(now), b = quartiles(best_after);
  std::printf("%zu states: one move's displacement, shortest of six: quartiles %.3f %.3f %.3f m; longest: %.3f %.3f %.3f m\n",
              shortest.size(), s[0], s[1], s[2], l[0], l[1], l[2]);
  std::printf("distance to the button now: %.3f %.3f %.3f m; after the best move: %.3f %.3f %.3f m\n", d[0], d[1], d[2],
              b[0], b[1], b[2]);
}
