// Domain randomization ("randomize" in a robot env's config, envs/randomization.hpp): action latency
// runs each action that many steps late, observation noise has the configured spread and spares the
// desired goal; masses, friction, damping, gains, placements, cameras, colours and light are drawn per
// episode within their ranges; all follow the reset seed and survive save/load; bad values are one
// clear error.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "../error_of.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/manipulation/manipulation_env.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"
#include "rdsim/envs/registry.hpp"

using Catch::Matchers::Contains;
using rdsim::test::error_of;

namespace {

std::unique_ptr<rdsim::Env> make(const nlohmann::json& env) {
  rdsim::ConfigReader r(env, "x.json", "env");
  return rdsim::make_env(rdsim::read_env_config(r));
}

std::vector<rdsim::Action> random_actions(const rdsim::Spec& spec, int n, std::uint64_t seed) {
  rdsim::Rng rng(seed);
  std::vector<rdsim::Action> actions;
  for (int i = 0; i < n; ++i) {
    if (spec.action.discrete) {
      actions.push_back(rdsim::Action::discrete(static_cast<int>(rng.below(static_cast<std::uint64_t>(spec.action.n)))));
    } else {
      Eigen::VectorXf v(spec.action.dim());
      for (int k = 0; k < v.size(); ++k) v[k] = static_cast<float>(rng.uniform(-1.0, 1.0));
      actions.push_back(rdsim::Action::continuous(v));
    }
  }
  return actions;
}

// One step of a noisy env and its plain twin with the same action: `a` and `b` become their next
// observations (after a reset where the episode ended). Returns whether the two rewards agree.
bool step_twins(rdsim::Env& noisy, rdsim::Env& plain, const rdsim::Action& action, rdsim::Observation& a,
                rdsim::Observation& b) {
  const rdsim::StepResult s = noisy.step(action), p = plain.step(action);
  if (s.terminated || s.truncated) {
    a = noisy.reset();
    b = plain.reset();
  } else {
    a = s.observation;
    b = p.observation;
  }
  return s.reward == p.reward;
}

}  // namespace

TEST_CASE("randomize: action latency runs each action that many steps late, the first ones the episode's first",
          "[randomize]") {
  for (const char* name : {"jaka_button", "push"}) {
    INFO(name);
    auto late = make({{"name", name}, {"randomize", {{"action_latency", 2}}}});
    auto plain = make({{"name", name}});
    const auto actions = random_actions(plain->spec(), 40, 7);
    rdsim::Observation a = late->reset(3), b = plain->reset(3);
    CHECK(a.values == b.values);
    for (int t = 0; t < 40; ++t) {
      const rdsim::StepResult s = late->step(actions[static_cast<std::size_t>(t)]);
      const rdsim::StepResult p = plain->step(actions[static_cast<std::size_t>(std::max(t - 2, 0))]);
      INFO("step " << t);
      REQUIRE(s.observation.values == p.observation.values);
      CHECK(s.reward == p.reward);
      if (s.terminated || s.truncated) break;
    }
    // A new episode starts with nothing pending: its first action runs at once again.
    a = late->reset(4);
    b = plain->reset(4);
    CHECK(late->step(actions[5]).observation.values == plain->step(actions[5]).observation.values);
  }
}

TEST_CASE("randomize: observation noise has the configured spread, spares the desired goal and follows the seed",
          "[randomize]") {
  auto noisy = make({{"name", "reach_goal"}, {"randomize", {{"observation_noise", 0.01}}}});
  auto plain = make({{"name", "reach_goal"}});
  const rdsim::GoalLayout& goal = plain->spec().goal;
  REQUIRE(goal.active());
  const auto actions = random_actions(plain->spec(), 200, 8);
  double sum = 0.0, squares = 0.0;
  int n = 0;
  std::vector<float> first_run;
  for (int run = 0; run < 2; ++run) {
    rdsim::Observation a = noisy->reset(11), b = plain->reset(11);
    for (std::size_t t = 0; t < actions.size(); ++t) {
      for (int i = 0; i < a.values.size(); ++i) {
        const double d = a.values[i] - b.values[i];
        if (i >= goal.desired_offset()) {
          CHECK(d == 0.0);
        } else if (run == 0) {
          sum += d;
          squares += d * d;
          ++n;
        }
        if (run == 0) first_run.push_back(a.values[i]);
        else CHECK(a.values[i] == first_run[static_cast<std::size_t>(t * static_cast<std::size_t>(a.values.size()) + static_cast<std::size_t>(i))]);
      }
      CHECK(step_twins(*noisy, *plain, actions[t], a, b));  // the noise is in what is observed, not in the state
    }
  }
  const double mean = sum / n, sd = std::sqrt(squares / n - mean * mean);
  INFO(n << " noisy values: mean " << mean << ", sd " << sd);
  CHECK(std::abs(mean) < 0.001);
  CHECK(sd == Approx(0.01).epsilon(0.05));
  // Another seed, other noise.
  CHECK(noisy->reset(12).values != noisy->reset(11).values);
}

TEST_CASE("randomize: a saved state continues the pending actions and the noise exactly", "[randomize]") {
  const nlohmann::json config = {{"name", "jaka_button"},
                                 {"randomize", {{"action_latency", 3}, {"observation_noise", 0.005}}}};
  auto a = make(config), b = make(config);
  const auto actions = random_actions(a->spec(), 30, 9);
  a->reset(5);
  for (int t = 0; t < 10; ++t) a->step(actions[static_cast<std::size_t>(t)]);
  auto* state = dynamic_cast<rdsim::EnvState*>(a.get());
  REQUIRE(state);
  const std::string saved = state->save_state();
  b->reset(99);
  dynamic_cast<rdsim::EnvState&>(*b).load_state(saved, "checkpoint.bin");
  for (int t = 10; t < 30; ++t) {
    const auto sa = a->step(actions[static_cast<std::size_t>(t)]), sb = b->step(actions[static_cast<std::size_t>(t)]);
    CHECK(sa.observation.values == sb.observation.values);
    CHECK(sa.reward == sb.reward);
  }
  std::string damaged = saved;
  damaged.resize(damaged.size() - 2);
  CHECK_THROWS_WITH(dynamic_cast<rdsim::EnvState&>(*b).load_state(damaged, "checkpoint.bin"), Contains("checkpoint.bin"));
}

TEST_CASE("randomize: bad values are one clear error", "[randomize][config]") {
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"randomize", {{"observation_noise", -0.1}}}}); }),
             Contains("env.randomize.observation_noise"));
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"randomize", {{"action_latency", -1}}}}); }),
             Contains("env.randomize.action_latency"));
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"max_steps", 50}, {"randomize", {{"action_latency", 50}}}}); }),
             Contains("env.randomize.action_latency: 50 steps is not shorter than jaka_button's episode (max_steps 50)"));
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"randomize", {{"mass", 0.3}}}}); }),
             Contains("env.randomize.mass"));
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"randomize", 3}}); }), Contains("env.randomize"));
  CHECK_THAT(error_of([] {
               make({{"name", "jaka_button"}, {"observation", "raw_pixels"}, {"randomize", {{"observation_noise", 0.01}}}});
             }),
             Contains("env.randomize.observation_noise") && Contains("ground_truth"));
  CHECK_THAT(error_of([] { make({{"name", "cartpole"}, {"randomize", {{"action_latency", 1}}}}); }),
             Contains("env.randomize"));
  // Latency alone works on pixels.
  CHECK_NOTHROW(make({{"name", "jaka_button"}, {"observation", "raw_pixels"}, {"randomize", {{"action_latency", 1}}}}));
}

namespace {

// The per-episode draws a ReachTask-based env applies (what envs/task_randomizer.hpp varies).
struct Physics {
  std::vector<double> link_mass, object_mass;
  std::vector<float> object_friction, joint_damping;
  float position_gain = 0.0f, velocity_gain = 0.0f;
  bool operator==(const Physics&) const = default;
};

Physics physics_of(const rdsim::ReachTask& task) {
  Physics p;
  const rdsim::Robot& robot = task.robot();
  for (int l = 0; l < static_cast<int>(robot.model().links.size()); ++l) p.link_mass.push_back(robot.link_inertia(l).mass);
  for (int d = 0; d < robot.dof(); ++d) p.joint_damping.push_back(robot.joint_damping(d));
  for (size_t i = 0; i < task.spec().statics.size(); ++i) {
    const int body = task.static_body(static_cast<int>(i));
    if (!task.world().is_free_body(body)) continue;
    p.object_mass.push_back(task.world().free_body_mass(body));
    p.object_friction.push_back(task.world().free_body_friction(body));
  }
  p.position_gain = robot.position_gain();
  p.velocity_gain = robot.velocity_gain();
  return p;
}

const rdsim::ReachTask& task_of(const rdsim::Env& env) {
  if (const auto* m = dynamic_cast<const rdsim::ManipulationEnv*>(&env)) return m->world();
  return dynamic_cast<const rdsim::ReachEnv&>(env).task();
}

const nlohmann::json physical = {{"mass_scale", {0.7, 1.3}},   {"friction_scale", {0.5, 1.5}},
                                 {"joint_damping", {0.1, 0.5}}, {"gain_scale", {0.8, 1.2}},
                                 {"placement_noise", 0.02}};

}  // namespace

TEST_CASE("randomize: masses, friction, damping and gains are drawn per episode within their ranges, from the seed",
          "[randomize]") {
  auto plain = make({{"name", "push"}});
  auto varied = make({{"name", "push"}, {"randomize", physical}});
  plain->reset(4);
  const Physics nominal = physics_of(task_of(*plain));
  REQUIRE(nominal.object_mass.size() == 1);
  varied->reset(4);
  const Physics first = physics_of(task_of(*varied));
  for (size_t l = 0; l < nominal.link_mass.size(); ++l) {
    CHECK(first.link_mass[l] >= 0.7 * nominal.link_mass[l] - 1e-12);
    CHECK(first.link_mass[l] <= 1.3 * nominal.link_mass[l] + 1e-12);
  }
  CHECK(first.object_mass[0] >= 0.7 * nominal.object_mass[0] - 1e-6);
  CHECK(first.object_mass[0] <= 1.3 * nominal.object_mass[0] + 1e-6);
  CHECK(first.object_friction[0] >= 0.5f * nominal.object_friction[0] - 1e-6f);
  CHECK(first.object_friction[0] <= 1.5f * nominal.object_friction[0] + 1e-6f);
  for (size_t d = 0; d < nominal.joint_damping.size(); ++d) {
    CHECK(first.joint_damping[d] >= nominal.joint_damping[d] + 0.1f - 1e-6f);
    CHECK(first.joint_damping[d] <= nominal.joint_damping[d] + 0.5f + 1e-6f);
  }
  CHECK(first.position_gain >= 0.8f * nominal.position_gain - 1e-6f);
  CHECK(first.position_gain <= 1.2f * nominal.position_gain + 1e-6f);
  CHECK(first.link_mass != nominal.link_mass);
  // The next episode draws again; the same seed draws the same; another seed other values.
  varied->reset();
  CHECK_FALSE(physics_of(task_of(*varied)) == first);
  varied->reset(4);
  CHECK(physics_of(task_of(*varied)) == first);
  varied->reset(5);
  CHECK_FALSE(physics_of(task_of(*varied)) == first);
  // The plain env's physics never changes.
  plain->reset(5);
  CHECK(physics_of(task_of(*plain)) == nominal);
}

TEST_CASE("randomize: the physical draws change what the same actions do, and placements move by up to the noise",
          "[randomize]") {
  for (const char* name : {"jaka_button", "push"}) {
    INFO(name);
    auto plain = make({{"name", name}});
    auto varied = make({{"name", name}, {"randomize", physical}});
    const auto p0 = plain->reset(8), v0 = varied->reset(8);
    if (std::string(name) == "jaka_button") {
      // The observation starts with target - effector: the target moved in x and y only.
      const Eigen::Vector3f moved = (v0.values.head<3>() - p0.values.head<3>()).eval();
      CHECK(std::abs(moved.z()) < 1e-6f);
      CHECK(moved.head<2>().cwiseAbs().maxCoeff() <= 0.02f + 1e-6f);
      CHECK(moved.head<2>().norm() > 0.0f);
    } else {
      // push: the cube (observation 7..9) and the goal (the last 3 values) moved in x and y only.
      const auto& pm = dynamic_cast<const rdsim::ManipulationEnv&>(*plain);
      const auto& vm = dynamic_cast<const rdsim::ManipulationEnv&>(*varied);
      const Eigen::Vector3f cube = vm.cube_position(0) - pm.cube_position(0), goal = vm.goals()[0] - pm.goals()[0];
      for (const Eigen::Vector3f& moved : {cube, goal}) {
        CHECK(std::abs(moved.z()) < 1e-6f);
        CHECK(moved.head<2>().cwiseAbs().maxCoeff() <= 0.02f + 1e-6f);
      }
      CHECK(cube != goal);
    }
    const auto actions = random_actions(plain->spec(), 20, 3);
    rdsim::Observation po = p0, vo = v0;
    for (const auto& a : actions) {
      po = plain->step(a).observation;
      vo = varied->step(a).observation;
    }
    CHECK(po.values != vo.values);
  }
}

TEST_CASE("randomize: a saved state keeps the episode's draws: a loaded env continues bit for bit", "[randomize]") {
  for (const char* name : {"jaka_button", "push"}) {
    INFO(name);
    nlohmann::json randomize = physical;
    randomize["observation_noise"] = 0.002;
    const nlohmann::json config = {{"name", name}, {"randomize", randomize}};
    auto a = make(config), b = make(config);
    const auto actions = random_actions(a->spec(), 40, 2);
    a->reset(7);
    for (int t = 0; t < 10; ++t) a->step(actions[static_cast<std::size_t>(t)]);
    const std::string saved = dynamic_cast<rdsim::EnvState&>(*a).save_state();
    dynamic_cast<rdsim::EnvState&>(*a).drop_caches();  // what training does at every update (env_state.hpp)
    b->reset(70);  // other draws, replaced by the loaded ones
    dynamic_cast<rdsim::EnvState&>(*b).load_state(saved, "checkpoint.bin");
    for (int t = 10; t < 40; ++t) {
      const auto sa = a->step(actions[static_cast<std::size_t>(t)]), sb = b->step(actions[static_cast<std::size_t>(t)]);
      REQUIRE(sa.observation.values == sb.observation.values);
      if (sa.terminated || sa.truncated) {
        CHECK(a->reset().values == b->reset().values);  // and the next episode's draws follow on
      }
    }
  }
}

TEST_CASE("randomize: camera, colour and light draws change the pixels, per episode and per seed", "[randomize][pixels]") {
  const nlohmann::json pixels = {{"name", "jaka_button"}, {"observation", "raw_pixels"}};
  nlohmann::json config = pixels;
  config["randomize"] = {{"camera_shift", 0.03}, {"camera_turn", 3.0}, {"camera_fov", 2.0}};
  auto plain = make(pixels), moved = make(config);
  const auto image = plain->reset(2).pixels;
  const auto first = moved->reset(2).pixels;
  CHECK(first != image);
  CHECK(moved->reset().pixels != first);
  CHECK(moved->reset(2).pixels == first);
  const auto& view = *dynamic_cast<const rdsim::ReachEnv&>(*moved).pixel_view();
  const auto& built = *dynamic_cast<const rdsim::ReachEnv&>(*plain).pixel_view();
  const Eigen::Vector3f shift = view.camera(0).eye - built.camera(0).eye;
  CHECK(shift.cwiseAbs().maxCoeff() <= 0.03f + 1e-6f);
  CHECK(std::abs(view.camera(0).fov_deg - built.camera(0).fov_deg) <= 2.0f + 1e-5f);
  const Eigen::Vector3f d0 = (built.camera(0).target - built.camera(0).eye).normalized();
  const Eigen::Vector3f d1 = (view.camera(0).target - view.camera(0).eye).normalized();
  // Yaw and pitch of at most 3 degrees each turn the view by at most about 4.3 degrees.
  CHECK(std::acos(std::clamp(d0.dot(d1), -1.0f, 1.0f)) <= 4.3f * static_cast<float>(M_PI) / 180.0f);

  {  // The spec known without drawing (what training asks first) is the pixel env's.
    rdsim::ConfigReader r(config, "x.json", "env");
    CHECK(rdsim::env_spec(rdsim::read_env_config(r)).observation.shape == moved->spec().observation.shape);
  }

  config["randomize"] = {{"colour_noise", 0.1}, {"light_turn", 10.0}};
  auto painted = make(config);
  CHECK(painted->reset(2).pixels != image);
  const auto& items = dynamic_cast<const rdsim::ReachEnv&>(*painted).pixel_view()->scene().items;
  const auto& built_items = built.scene().items;
  REQUIRE(items.size() == built_items.size());
  for (size_t i = 0; i < items.size(); ++i) CHECK((items[i].rgba - built_items[i].rgba).cwiseAbs().maxCoeff() <= 0.1f + 1e-6f);
}

TEST_CASE("randomize: bad ranges and view draws without pixels are one clear error", "[randomize][config]") {
  CHECK_THAT(error_of([] { make({{"name", "push"}, {"randomize", {{"mass_scale", {1.3, 0.7}}}}}); }),
             Contains("env.randomize.mass_scale: expected [lo, hi] with lo <= hi"));
  CHECK_THAT(error_of([] { make({{"name", "push"}, {"randomize", {{"friction_scale", {0.5}}}}}); }),
             Contains("env.randomize.friction_scale: expected [lo, hi]"));
  CHECK_THAT(error_of([] { make({{"name", "push"}, {"randomize", {{"joint_damping", {-1, 1}}}}}); }),
             Contains("env.randomize.joint_damping"));
  CHECK_THAT(error_of([] { make({{"name", "push"}, {"randomize", {{"gain_scale", 1.1}}}}); }),
             Contains("env.randomize.gain_scale"));
  CHECK_THAT(error_of([] { make({{"name", "push"}, {"randomize", {{"placement_noise", -0.01}}}}); }),
             Contains("env.randomize.placement_noise"));
  CHECK_THAT(error_of([] { make({{"name", "push"}, {"randomize", {{"colour_noise", 0.1}}}}); }),
             Contains("env.randomize.colour_noise: applies to raw-pixel observations only"));
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"observation", "raw_pixels"}, {"randomize", {{"camera_turn", 45}}}}); }),
             Contains("env.randomize.camera_turn"));
}

TEST_CASE("randomize: observe_latency puts the actions still to run into the observation", "[randomize]") {
  SECTION("Discrete: one-hot, oldest first, zeros before the first action") {
    auto plain = make({{"name", "jaka_button"}});
    auto env = make({{"name", "jaka_button"}, {"randomize", {{"action_latency", 2}, {"observe_latency", true}}}});
    const int inner = plain->spec().observation.size();
    REQUIRE(env->spec().observation.size() == inner + 12);
    CHECK(env->spec().observation.low.tail(12).isZero());
    CHECK(env->spec().observation.high.tail(12).isOnes());
    const auto first = env->reset(3);
    CHECK(first.values.head(inner) == plain->reset(3).values);
    CHECK(first.values.tail(12).isZero());
    Eigen::VectorXf expected = Eigen::VectorXf::Zero(12);
    expected[3] = expected[6 + 3] = 1.0f;  // the first action fills the queue
    CHECK(env->step(rdsim::Action::discrete(3)).observation.values.tail(12) == expected);
    expected.setZero();
    expected[3] = expected[6 + 1] = 1.0f;
    CHECK(env->step(rdsim::Action::discrete(1)).observation.values.tail(12) == expected);
  }
  SECTION("Box, in a goal env: the clipped values, between the env's own values and its goals") {
    auto plain = make({{"name", "push"}});
    auto env = make({{"name", "push"}, {"randomize", {{"action_latency", 1}, {"observe_latency", true}}}});
    const rdsim::GoalLayout& g = plain->spec().goal;
    const rdsim::GoalLayout& h = env->spec().goal;
    REQUIRE(h.observation == g.observation + 3);
    CHECK(h.points == g.points);
    plain->reset(5);
    env->reset(5);
    const auto a = rdsim::Action::continuous(Eigen::Vector3f(0.5f, -3.0f, 0.25f));
    const auto p = plain->step(a).observation.values, o = env->step(a).observation.values;
    CHECK(o.head(g.observation) == p.head(g.observation));
    CHECK(o.segment(g.observation, 3) == Eigen::Vector3f(0.5f, -1.0f, 0.25f));
    CHECK(o.tail(2 * g.goal_size()) == p.tail(2 * g.goal_size()));
    // A value that is not a number waits as 0, as the env runs it.
    const auto nan = rdsim::Action::continuous(Eigen::Vector3f(std::nanf(""), 0.5f, 0.0f));
    CHECK(env->step(nan).observation.values.segment(g.observation, 3) == Eigen::Vector3f(0.0f, 0.5f, 0.0f));
  }
  SECTION("latency_slots: room for more actions than the latency, zeros where none wait") {
    auto none = make({{"name", "push"}, {"randomize", {{"observe_latency", true}, {"latency_slots", 2}}}});
    auto some = make({{"name", "push"}, {"randomize", {{"action_latency", 2}, {"random_latency", true},
                                                        {"observe_latency", true}, {"latency_slots", 3}}}});
    auto plain = make({{"name", "push"}});
    const int inner = plain->spec().observation.size();
    CHECK(none->spec().observation.size() == inner + 6);
    CHECK(some->spec().observation.size() == inner + 9);
    plain->reset(4);
    none->reset(4);
    const auto a = rdsim::Action::continuous(Eigen::Vector3f(0.5f, 0.5f, 0.0f));
    const auto o = none->step(a).observation.values, p = plain->step(a).observation.values;
    const int split = plain->spec().goal.observation;
    CHECK(o.segment(split, 6).isZero());  // no latency: the action ran at once
    CHECK(o.head(split) == p.head(split));
  }
  CHECK_THAT(error_of([] { make({{"name", "push"}, {"randomize", {{"observe_latency", true}}}}); }),
             Contains("env.randomize.observe_latency: needs action_latency > 0"));
  CHECK_THAT(error_of([] {
               make({{"name", "push"}, {"randomize", {{"action_latency", 3}, {"observe_latency", true}, {"latency_slots", 2}}}});
             }),
             Contains("env.randomize.latency_slots: 2 slots cannot hold an action_latency of 3"));
  CHECK_THAT(error_of([] { make({{"name", "push"}, {"randomize", {{"latency_slots", 2}}}}); }),
             Contains("env.randomize.latency_slots: has no effect without observe_latency"));
}

TEST_CASE("randomize: random_latency runs each episode with a latency of 0..action_latency steps, from the seed",
          "[randomize]") {
  std::vector<std::unique_ptr<rdsim::Env>> fixed;
  for (int latency = 0; latency <= 2; ++latency)
    fixed.push_back(latency == 0 ? make({{"name", "push"}})
                                 : make({{"name", "push"}, {"randomize", {{"action_latency", latency}}}}));
  auto random = make({{"name", "push"}, {"randomize", {{"action_latency", 2}, {"random_latency", true}}}});
  const auto actions = random_actions(random->spec(), 4, 1);
  std::vector<int> seen(3, 0);
  for (std::uint64_t seed = 1; seed <= 15; ++seed) {
    random->reset(seed);
    for (auto& f : fixed) f->reset(seed);
    Eigen::VectorXf last;
    std::vector<Eigen::VectorXf> ends(3);
    for (const auto& a : actions) {
      last = random->step(a).observation.values;
      for (int l = 0; l < 3; ++l) ends[static_cast<size_t>(l)] = fixed[static_cast<size_t>(l)]->step(a).observation.values;
    }
    if (ends[0] == ends[1] || ends[1] == ends[2]) continue;  // an episode that ended at once tells nothing
    int matches = 0;
    for (int l = 0; l < 3; ++l)
      if (ends[static_cast<size_t>(l)] == last) {
        ++matches;
        ++seen[static_cast<size_t>(l)];
      }
    INFO("seed " << seed);
    CHECK(matches == 1);  // exactly one latency explains the episode
  }
  CHECK(seen[0] > 0);
  CHECK(seen[1] > 0);
  CHECK(seen[2] > 0);
  CHECK_THAT(error_of([] { make({{"name", "push"}, {"randomize", {{"random_latency", true}}}}); }),
             Contains("env.randomize.random_latency: needs action_latency > 0"));
}

TEST_CASE("observation parts: every value of a robot task's vector named, in order", "[randomize][contract]") {
  using Parts = std::vector<std::pair<std::string, int>>;
  const auto parts_of = [](const nlohmann::json& config) {
    Parts out;
    const auto env = make(config);
    for (const rdsim::ObservationPart& p : env->spec().observation.parts) out.emplace_back(p.name, p.size);
    return out;
  };
  CHECK(parts_of({{"name", "push"}}) == Parts{{"effector_position", 3}, {"effector_velocity", 3}, {"cube1_position", 3},
                                             {"cube1_orientation", 4}, {"cube1_velocity", 3}, {"cube1_angular_velocity", 3},
                                             {"cube1_from_effector", 3}, {"achieved_goal", 3}, {"desired_goal", 3}});
  const Parts stack = parts_of({{"name", "stack"}});
  CHECK(stack[2] == std::pair<std::string, int>{"finger_opening", 1});
  CHECK(stack[8] == std::pair<std::string, int>{"cube2_position", 3});
  CHECK(stack.back() == std::pair<std::string, int>{"desired_goal", 6});
  CHECK(parts_of({{"name", "jaka_obstacle"}}) ==
        Parts{{"target_from_effector", 3}, {"effector_from_column", 3}, {"effector_position", 3},
              {"wrist_2_link_from_column", 3}, {"wrist_3_link_from_column", 3}});
  CHECK(parts_of({{"name", "jaka_button"}, {"observation_layout", "relative"}}) == Parts{{"effector_from_target", 3}});
  // observe_latency's queue is a part too, where its values go: before a goal env's goals.
  const Parts queued = parts_of({{"name", "push"}, {"randomize", {{"action_latency", 2}, {"observe_latency", true}}}});
  CHECK(queued[queued.size() - 3] == std::pair<std::string, int>{"pending_actions", 6});
  CHECK(parts_of({{"name", "jaka_button"}, {"randomize", {{"action_latency", 1}, {"observe_latency", true}}}}).back() ==
        std::pair<std::string, int>{"pending_actions", 6});
}

TEST_CASE("randomize: observation_noise_parts gives each named part its own spread, the rest observation_noise",
          "[randomize]") {
  const nlohmann::json parts = {{"cube1_position", 0.02}, {"effector_velocity", 0.0}};
  auto noisy = make({{"name", "push"}, {"randomize", {{"observation_noise", 0.001}, {"observation_noise_parts", parts}}}});
  auto plain = make({{"name", "push"}});
  const rdsim::ObservationSpace& space = noisy->spec().observation;
  const auto [cube, cube_size] = space.part("cube1_position");
  const auto [velocity, velocity_size] = space.part("effector_velocity");
  const auto [desired, desired_size] = space.part("desired_goal");
  const auto actions = random_actions(plain->spec(), 100, 3);
  std::vector<double> cube_noise, other_noise;
  rdsim::Observation a = noisy->reset(21), b = plain->reset(21);
  for (const rdsim::Action& action : actions) {
    for (int i = 0; i < a.values.size(); ++i) {
      const double d = a.values[i] - b.values[i];
      if ((i >= velocity && i < velocity + velocity_size) || i >= desired) CHECK(d == 0.0);
      else if (i >= cube && i < cube + cube_size) cube_noise.push_back(d);
      else other_noise.push_back(d);
    }
    step_twins(*noisy, *plain, action, a, b);
  }
  const auto sd = [](const std::vector<double>& v) {
    double squares = 0.0;
    for (double x : v) squares += x * x;
    return std::sqrt(squares / static_cast<double>(v.size()));
  };
  CHECK(sd(cube_noise) == Approx(0.02).epsilon(0.15));
  CHECK(sd(other_noise) == Approx(0.001).epsilon(0.15));
  (void)cube_size;
  (void)desired_size;
}

TEST_CASE("randomize: observation_noise_parts names parts the env has", "[randomize][config]") {
  const auto with_parts = [](const char* env, const nlohmann::json& parts) {
    return error_of([&] { make({{"name", env}, {"randomize", {{"observation_noise_parts", parts}}}}); });
  };
  CHECK_THAT(with_parts("push", {{"cube_position", 0.01}}),
             Contains("env.randomize.observation_noise_parts: \"cube_position\" is not a part of push's observation") &&
                 Contains("did you mean \"cube1_position\"") && Contains("its parts: effector_position, "));
  CHECK_THAT(with_parts("push", {{"desired_goal", 0.01}}), Contains("desired_goal") && Contains("stays exact"));
  CHECK_THAT(with_parts("push", {{"cube1_position", -0.01}}), Contains("env.randomize.observation_noise_parts.cube1_position: expected a number in [0, 1000]"));
  CHECK_THAT(with_parts("push", {0.01, 0.02}), Contains("env.randomize.observation_noise_parts: expected an object"));
  CHECK_THAT(error_of([] {
               make({{"name", "jaka_button"},
                     {"observation", "raw_pixels"},
                     {"randomize", {{"observation_noise_parts", {{"effector_position", 0.01}}}}}});
             }),
             Contains("env.randomize.observation_noise_parts") && Contains("ground_truth"));
  CHECK_NOTHROW(make({{"name", "jaka_obstacle"}, {"randomize", {{"observation_noise_parts", {{"effector_from_column", 0.01}}}}}}));
}
