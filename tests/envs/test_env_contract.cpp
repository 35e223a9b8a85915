// The contract every registered env keeps (rdsim's one env checker, in the spirit of SB3's
// check_env), run over env_registry() in every observation mode the env offers: spaces, dtypes
// and bounds, same seed = bit-identical trajectories, truncation exactly at max_steps, stepping
// after the end (core/env.hpp: harmless; a bad action is an error), render with rgb_array.
// A new env gets all of this by being registered; its own physics and task rules go in
// tests/envs/test_<env>.cpp.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "env_test_util.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/manipulation/manipulation_options.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"

using namespace rdsim;

namespace {

struct Case {
  std::string label;
  EnvConfig config;
};

// Every registered env with its defaults (random targets where it has them, so the seed decides
// more), and for pixel envs small raw-pixel images (not square, so height and width cannot swap
// unnoticed), with one and two cameras.
std::vector<Case> contract_cases() {
  std::vector<Case> cases;
  for (const EnvEntry& entry : env_registry()) {
    EnvConfig c = default_env_config(entry.name);
    if (auto* reach = c.find<ReachOptions>()) reach->random_target = true;
    // Goal tasks end on success: a goal no random walk reaches keeps every episode its full length.
    if (auto* goal = c.find<ManipulationOptions>()) goal->distance_threshold = 1e-3;
    cases.push_back({entry.name + ", ground_truth", c});
    if (c.find<ManipulationOptions>()) {
      EnvConfig joints = c;
      joints.get<ManipulationOptions>().control = ArmControl::Joints;
      cases.push_back({entry.name + ", ground_truth, control joints", joints});
    }
    if (!entry.supports_pixels) continue;
    c.observation = ObservationMode::RawPixels;
    c.image_width = 24;
    c.image_height = 16;
    cases.push_back({entry.name + ", raw_pixels", c});
    c.multi_view = true;
    cases.push_back({entry.name + ", raw_pixels, multi_view", c});
    c.image_channels = "rgb_depth_segmentation";
    cases.push_back({entry.name + ", raw_pixels, multi_view, depth and segmentation", c});
  }
  // The paper presets (configs/paper/): the same contract with RobotDrlSim's task semantics.
  for (const char* name : {"jaka_button", "jaka_obstacle", "inmoov_tomato"}) {
    cases.push_back({std::string(name) + ", paper preset", test::paper_env_config(name)});
    EnvConfig c = test::paper_env_config(name, /*pixels=*/true);
    c.image_width = 24;
    c.image_height = 16;
    cases.push_back({std::string(name) + ", paper preset, raw_pixels", c});
  }
  return cases;
}

void check_spaces(const Spec& spec, const EnvConfig& config) {
  CHECK(spec.env_name == config.name);
  CHECK(spec.max_episode_steps == config.max_steps);
  CHECK(spec.control_dt >= 0.0);
  const ObservationSpace& o = spec.observation;
  const bool pixels = config.observation == ObservationMode::RawPixels;
  // A goal env's images carry its goals beside them, which Spec::goal indexes among the values.
  CHECK(o.vector_size == (pixels && spec.goal.active() ? 2 * spec.goal.goal_size() : 0));
  if (pixels && spec.goal.active()) {
    CHECK(spec.goal.observation == (o.type == ObsType::Float32 ? o.size() : 0));
    CHECK(spec.goal.size() == o.value_count());
    CHECK(o.parts == std::vector<ObservationPart>{{"achieved_goal", spec.goal.goal_size()}, {"desired_goal", spec.goal.goal_size()}});
  } else if (pixels) {
    CHECK(o.parts.empty());
  }
  if (o.type == ObsType::Float32 && pixels) {
    // Stacked Float32 channels (image_channels): r, g, b, depth, segmentation per camera.
    CHECK(config.image_channels == "rgb_depth_segmentation");
    CHECK(o.shape == std::vector<int>{config.image_height, config.image_width, config.multi_view ? 10 : 5});
    REQUIRE(o.low.size() == o.value_count());
    REQUIRE(o.high.size() == o.value_count());
    CHECK((o.low.array() <= o.high.array()).all());
  } else if (o.type == ObsType::Float32) {
    REQUIRE(o.shape.size() == 1);
    CHECK(o.shape[0] > 0);
    REQUIRE(o.low.size() == o.shape[0]);
    REQUIRE(o.high.size() == o.shape[0]);
    CHECK((o.low.array() <= o.high.array()).all());
    CHECK(config.observation == ObservationMode::GroundTruth);
    // Its parts name every value once, a goal env's goals last.
    int named = 0;
    std::vector<std::string> names;
    for (const ObservationPart& p : o.parts) {
      CHECK(p.size > 0);
      CHECK(std::find(names.begin(), names.end(), p.name) == names.end());
      names.push_back(p.name);
      named += p.size;
    }
    CHECK(named == o.size());
    if (spec.goal.active()) {
      REQUIRE(names.size() >= 3);
      CHECK(o.part("achieved_goal") == std::pair{spec.goal.achieved_offset(), spec.goal.goal_size()});
      CHECK(o.part("desired_goal") == std::pair{spec.goal.desired_offset(), spec.goal.goal_size()});
    }
  } else {
    const int channels = config.multi_view ? 6 : 3;
    CHECK(o.shape == std::vector<int>{config.image_height, config.image_width, channels});
    CHECK(o.low.size() == o.vector_size);  // UInt8: 0..255; bounds for the goals beside them
    CHECK(o.high.size() == o.vector_size);
    CHECK(pixels);
  }
  const ActionSpace& a = spec.action;
  if (a.discrete) {
    CHECK(a.n > 0);
    CHECK(a.dim() == 1);
  } else {
    REQUIRE(a.low.size() > 0);
    REQUIRE(a.high.size() == a.low.size());
    CHECK((a.low.array() < a.high.array()).all());
  }
}

// The observation has the space's dtype and size, and Float32 values are finite and in bounds.
void check_observation(const ObservationSpace& space, const Observation& obs) {
  REQUIRE(obs.values.size() == space.value_count());
  CHECK(obs.pixels.size() == static_cast<size_t>(space.byte_count()));
  if (space.value_count() == 0) return;
  CHECK(obs.values.allFinite());
  INFO("observation " << obs.values.tail(std::min<Eigen::Index>(obs.values.size(), 64)).transpose());
  CHECK((obs.values.array() >= space.low.array()).all());
  CHECK((obs.values.array() <= space.high.array()).all());
}

Action random_action(const ActionSpace& a, Rng& rng) {
  if (a.discrete) return Action::discrete(static_cast<int>(rng.below(static_cast<std::uint64_t>(a.n))));
  Eigen::VectorXf v(a.low.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = static_cast<float>(rng.uniform(a.low[i], a.high[i]));
  return Action::continuous(std::move(v));
}

// Back and forth along the first axis (discrete 0, 1, 0, ...; a box action's first component
// -1, +1, ...): episodes neither fail nor succeed within a few steps.
Action back_and_forth(const ActionSpace& a, int t) {
  if (a.discrete) return Action::discrete(t % 2);
  Eigen::VectorXf v = Eigen::VectorXf::Zero(a.low.size());
  v[0] = t % 2 ? a.high[0] : a.low[0];
  return Action::continuous(std::move(v));
}

// Everything a run produces, as bytes: observations, rewards and episode flags.
std::vector<float> trace(const EnvConfig& config, std::uint64_t seed, int steps) {
  auto env = make_env(config);
  Rng actions(99);
  std::vector<float> out;
  auto add = [&](const Observation& o) {
    out.insert(out.end(), o.values.data(), o.values.data() + o.values.size());
    out.insert(out.end(), o.pixels.begin(), o.pixels.end());
  };
  add(env->reset(seed));
  for (int k = 0; k < steps; ++k) {
    const StepResult r = env->step(random_action(env->spec().action, actions));
    check_observation(env->spec().observation, r.observation);
    add(r.observation);
    out.push_back(r.reward);
    out.push_back(static_cast<float>(r.terminated) + 2.0f * static_cast<float>(r.truncated));
    if (r.terminated || r.truncated) add(env->reset());  // no seed: the stream continues
  }
  return out;
}

bool same_observation(const Observation& a, const Observation& b) {
  return a.values.size() == b.values.size() && a.values == b.values && a.pixels == b.pixels;
}

}  // namespace

TEST_CASE("env contract: spaces, dtypes and observation bounds", "[envs][contract]") {
  for (const Case& c : contract_cases()) {
    INFO(c.label);
    auto env = make_env(c.config);
    const Spec& spec = env->spec();
    check_spaces(spec, c.config);
    Rng actions(5);
    for (std::uint64_t seed = 0; seed < 3; ++seed) {
      check_observation(spec.observation, env->reset(seed));
      for (int k = 0; k < 40; ++k) {
        const StepResult r = env->step(random_action(spec.action, actions));
        check_observation(spec.observation, r.observation);
        CHECK(std::isfinite(r.reward));
        if (r.terminated || r.truncated) break;
      }
    }
  }
}

TEST_CASE("env contract: the same seed gives bit-identical trajectories, another seed does not", "[envs][contract]") {
  for (const Case& c : contract_cases()) {
    INFO(c.label);
    const int steps = c.config.observation == ObservationMode::RawPixels ? 40 : 250;  // resets included
    const std::vector<float> a = trace(c.config, 7, steps);
    CHECK(a == trace(c.config, 7, steps));  // exact float and byte equality
    // The paper's fixed-button preset draws nothing (fixed button, no noise): every seed is the same.
    const ReachOptions* reach = c.config.find<ReachOptions>();  // the other envs draw their start
    const bool draws = !reach || reach->random_target || reach->reset_noise > 0.0 || reach->move_noise > 0.0;
    if (draws)
      CHECK(a != trace(c.config, 8, steps));
    else
      CHECK(a == trace(c.config, 8, steps));
  }
}

TEST_CASE("env contract: truncated exactly at max_steps, and stepping after the end is harmless", "[envs][contract]") {
  for (Case c : contract_cases()) {
    INFO(c.label);
    c.config.max_steps = 12;
    auto env = make_env(c.config);
    const Spec& spec = env->spec();
    env->reset(1);
    StepResult last;
    for (int t = 1; t <= 12; ++t) {
      INFO("step " << t);
      last = env->step(back_and_forth(spec.action, t));
      REQUIRE_FALSE(last.terminated);
      CHECK(last.truncated == (t == 12));
    }
    // After the end, before reset: nothing moves, reward 0, terminated (core/env.hpp).
    for (int t = 0; t < 3; ++t) {
      const StepResult after = env->step(back_and_forth(spec.action, t));
      CHECK(after.terminated);
      CHECK_FALSE(after.truncated);
      CHECK(after.reward == 0.0f);
      CHECK(same_observation(after.observation, last.observation));
    }
    // A bad action is an error, ended episode or not.
    const Action bad = spec.action.discrete ? Action::discrete(spec.action.n)
                                            : Action::continuous(Eigen::VectorXf::Zero(spec.action.dim() + 1));
    CHECK_THROWS_AS(env->step(bad), Error);
    env->reset(2);
    CHECK_THROWS_AS(env->step(bad), Error);
    CHECK_THROWS_AS(env->step(spec.action.discrete ? Action::discrete(-1) : Action::continuous(Eigen::VectorXf())), Error);
  }
}

TEST_CASE("env contract: render draws frames with render_mode rgb_array, and only then", "[envs][contract]") {
  for (const EnvEntry& entry : env_registry()) {
    INFO(entry.name);
    EnvConfig config = default_env_config(entry.name);
    auto plain = make_env(config);
    Image frame;
    CHECK_FALSE(plain->render(frame));
    if (!env_reads(entry, "render_mode")) continue;
    config.render_mode = RenderMode::RgbArray;
    config.render_width = 40;
    config.render_height = 30;
    auto drawn = make_env(config);
    const Observation first = drawn->reset(3);
    CHECK(same_observation(first, plain->reset(3)));  // drawing for people changes nothing the agent sees
    REQUIRE(drawn->render(frame));
    CHECK(frame.width == 40);
    CHECK(frame.height == 30);
    REQUIRE(frame.rgb.size() == 40u * 30u * 3u);
    const auto [lo, hi] = std::minmax_element(frame.rgb.begin(), frame.rgb.end());
    CHECK(*hi - *lo > 50);  // a scene, not a blank frame
    const std::vector<std::uint8_t> before = frame.rgb;
    for (int k = 0; k < 10; ++k) drawn->step(back_and_forth(drawn->spec().action, 1));
    REQUIRE(drawn->render(frame));
    CHECK(frame.rgb != before);  // frames follow the simulation
  }
}

TEST_CASE("env contract: each env publishes the spec its header documents", "[envs][contract]") {
  struct Published {
    const char* name;
    int observation_size;  // ground truth
    int actions;           // Discrete(n) by default; a Box's size when !discrete
    int max_steps;
    double control_dt;     // s
    bool discrete = true;
  };
  const Published table[] = {
      {"cartpole", 4, 2, 500, 0.02},
      {"jaka_button", 6, 6, 200, 1.0 / 240.0},
      {"jaka_obstacle", 15, 6, 300, 1.0 / 240.0},
      {"inmoov_tomato", 6, 6, 400, 1.0 / 240.0},
      {"pendulum", 3, 1, 200, 0.05, false},
      {"reach", 6, 6, 200, 1.0 / 240.0},
      // Goal tasks: observation + achieved goal + desired goal (envs/manipulation/manipulation_env.hpp).
      {"reach_goal", 6 + 3 + 3, 3, 50, 0.04, false},
      {"push", 6 + 16 + 3 + 3, 3, 50, 0.04, false},
      {"pick_and_place", 7 + 16 + 3 + 3, 4, 50, 0.04, false},
      {"stack", 7 + 2 * 16 + 6 + 6, 4, 100, 0.04, false},
  };
  CHECK(std::size(table) == env_registry().size());  // a new env adds its row
  for (const Published& p : table) {
    INFO(p.name);
    const auto env = make_env(default_env_config(p.name));
    const Spec& s = env->spec();
    CHECK(s.observation.shape == std::vector<int>{p.observation_size});
    CHECK(s.action.discrete == p.discrete);
    CHECK((p.discrete ? s.action.n : s.action.dim()) == p.actions);
    CHECK(s.max_episode_steps == p.max_steps);
    CHECK(s.control_dt == Approx(p.control_dt));
  }
}
