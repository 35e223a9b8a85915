// The manipulation tasks (push, pick_and_place, stack, reach_goal): the goal-conditioned layout and
// reward, the scripted expert's success on both arms (the JAKA with rdsim's gripper, pybullet_data's
// Panda), a held cube that does not slip, exact save/load, and one clear error per bad option.
// The env contract (spaces, determinism, truncation, stepping after the end) is test_env_contract's.
//   ./build/test_envs "[.demo]"   also writes docs/manipulation_panda_<task>.png (the docs' pictures).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "env_test_util.hpp"
#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/data_dir.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/envs/arm_options.hpp"
#include "rdsim/envs/manipulation/manipulation_env.hpp"
#include "rdsim/envs/manipulation/manipulation_expert.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/render/png.hpp"

using namespace rdsim;

namespace {

const char* const kTasks[] = {"reach_goal", "push", "pick_and_place", "stack"};

std::string pybullet_data() { return RDSIM_PYBULLET_DATA; }

// pybullet_data's Franka Panda with its own fingers, gripper pointing down over the task area.
EnvConfig panda_config(const std::string& task) {
  EnvConfig c = default_env_config(task);
  ArmOptions& arm = c.get<ArmOptions>();
  arm.urdf = pybullet_data() + "/franka_panda/panda.urdf";
  arm.effector_link = "panda_grasptarget";
  c.get<ManipulationOptions>().finger_joints = {"panda_finger_joint1", "panda_finger_joint2"};
  arm.home_pose = {0.0, 0.41, 0.0, -1.85, 0.0, 2.26, 0.79};  // panda-gym's neutral pose
  arm.base_position = {-0.05, 0.0, 0.0};  // the task area within easy reach
  return c;
}

// The default 10 physics steps of 4 ms, and the fastest setting benchmarked (docs/benchmarks.md):
// 4 of 10 ms, the same 40 ms per env step.
void use_substeps(EnvConfig& c, int substeps) {
  c.get<ManipulationOptions>().substeps = substeps;
  c.get<ManipulationOptions>().physics_step = 0.04 / substeps;
}

struct ExpertRun {
  int successes = 0;
  int episodes = 0;
};

ExpertRun run_expert(const EnvConfig& config, int episodes) {
  auto env = make_env(config);
  ManipulationExpert expert(*env);
  ExpertRun run;
  for (int e = 0; e < episodes; ++e) {
    env->reset(static_cast<std::uint64_t>(1000 + e));
    expert.reset();
    StepResult r;
    do r = env->step(expert.act());
    while (!r.terminated && !r.truncated);
    run.successes += r.info.success ? 1 : 0;
    ++run.episodes;
  }
  return run;
}

}  // namespace

TEST_CASE("Manipulation tasks declare the goal layout and reward of their spec", "[envs][manipulation]") {
  for (const char* name : kTasks) {
    INFO(name);
    auto env = make_env(default_env_config(name));
    const Spec& spec = env->spec();
    const GoalLayout& g = spec.goal;
    REQUIRE(g.active());
    CHECK(g.size() == spec.observation.size());
    CHECK(spec.max_episode_steps == (std::string(name) == "stack" ? 100 : 50));  // panda-gym's
    CHECK(spec.control_dt == Approx(0.04));
    const int cubes = std::string(name) == "stack" ? 2 : std::string(name) == "reach_goal" ? 0 : 1;
    CHECK(g.points == std::max(cubes, 1));
    const bool blocked = std::string(name) == "push" || std::string(name) == "reach_goal";
    CHECK(spec.action.dim() == (blocked ? 3 : 4));
    CHECK(g.observation == 6 + (blocked ? 0 : 1) + 16 * cubes);

    const auto* m = dynamic_cast<ManipulationEnv*>(env.get());
    REQUIRE(m);
    Observation o = env->reset(7);
    const float* achieved = o.values.data() + g.achieved_offset();
    const float* desired = o.values.data() + g.desired_offset();
    for (int p = 0; p < g.points; ++p) {
      const Eigen::Vector3f want = cubes ? m->cube_position(p) : m->world().ee_position();
      CHECK((Eigen::Map<const Eigen::Vector3f>(achieved + 3 * p) - want).norm() < 1e-6f);
      CHECK((Eigen::Map<const Eigen::Vector3f>(desired + 3 * p) - m->goals()[static_cast<size_t>(p)]).norm() < 1e-6f);
    }
    // The reward step() gives equals compute_reward on the observation's goals, one row or a batch.
    Rng rng(3);
    std::vector<float> achieved_rows, desired_rows, rewards;
    for (int t = 0; t < 20; ++t) {
      Eigen::VectorXf a(spec.action.dim());
      for (int i = 0; i < a.size(); ++i) a[i] = static_cast<float>(rng.uniform(-1.0, 1.0));
      const StepResult r = env->step(Action::continuous(a));
      const float* v = r.observation.values.data();
      CHECK(g.reward_of(v + g.achieved_offset(), v + g.desired_offset()) == r.reward);
      CHECK(g.is_success(v + g.achieved_offset(), v + g.desired_offset()) == r.info.success);
      achieved_rows.insert(achieved_rows.end(), v + g.achieved_offset(), v + g.achieved_offset() + g.goal_size());
      desired_rows.insert(desired_rows.end(), v + g.desired_offset(), v + g.desired_offset() + g.goal_size());
      rewards.push_back(r.reward);
      if (r.terminated || r.truncated) break;
    }
    std::vector<float> batch(rewards.size());
    g.compute_reward(achieved_rows.data(), desired_rows.data(), static_cast<int>(rewards.size()), batch.data());
    CHECK(batch == rewards);
  }
}

TEST_CASE("Goal rewards: sparse needs every point within the threshold, partial pays per point, dense is minus the distance",
          "[envs][manipulation]") {
  GoalLayout g{.observation = 0, .points = 2, .distance_threshold = 0.05f, .reward = GoalReward::Sparse};
  const float desired[] = {0, 0, 0, 0, 0, 0.04f};
  const float near[] = {0.03f, 0, 0, 0, 0.04f, 0.04f};
  const float half[] = {0.03f, 0, 0, 0, 0.06f, 0.04f};
  CHECK(g.reward_of(near, desired) == 0.0f);
  CHECK(g.reward_of(half, desired) == -1.0f);
  const float none[] = {0.06f, 0, 0, 0, 0.06f, 0.04f};
  g.reward = GoalReward::Partial;
  CHECK(g.reward_of(near, desired) == 0.0f);
  CHECK(g.reward_of(half, desired) == -0.5f);
  CHECK(g.reward_of(none, desired) == -1.0f);
  CHECK(goal_reward_from_string("partial") == GoalReward::Partial);
  CHECK(goal_reward_from_string(to_string(GoalReward::Dense)) == GoalReward::Dense);
  CHECK_FALSE(goal_reward_from_string("shaped"));
  g.reward = GoalReward::Dense;
  CHECK(g.reward_of(half, desired) == Approx(-std::sqrt(0.03f * 0.03f + 0.06f * 0.06f)));
}

// Measured on seeds 1000-1199 (Intel Xeon, 2026-11-29): reach_goal 200, push 196, pick_and_place 200,
// stack 198 of 200.
TEST_CASE("The scripted expert solves every manipulation task with the JAKA and its gripper", "[envs][manipulation][expert]") {
  for (const char* name : kTasks) {
    const ExpertRun run = run_expert(default_env_config(name), 200);
    INFO(name << ": " << run.successes << " of " << run.episodes);
    CHECK(run.successes >= 190);  // >= 95 %
  }
}

TEST_CASE("The scripted expert recovers from a missed first grasp", "[envs][manipulation][expert]") {
  for (const char* name : {"pick_and_place", "stack"}) {
    auto env = make_env(default_env_config(name));
    auto& m = dynamic_cast<ManipulationEnv&>(*env);
    ManipulationExpert expert(*env);
    int successes = 0, missed = 0;
    const int episodes = 20;
    for (int e = 0; e < episodes; ++e) {
      env->reset(static_cast<std::uint64_t>(2000 + e));
      expert.reset();
      // m: beside the cube along x (across the fingers, which open along y), either side in turn.
      expert.miss_first_grasp(Eigen::Vector2f(e % 2 ? 0.05f : -0.05f, 0.004f * static_cast<float>(e % 5 - 2)));
      bool closed_beside = false;
      StepResult r;
      do {
        r = env->step(expert.act());
        // The fingers shut on nothing, 4 cm or more from the cube that has not moved off the table.
        const Eigen::Vector3f ee = m.world().ee_position(), cube = m.cube_position(0);
        if (m.finger_opening() < TaskArea::cube_size - 0.005f && (ee - cube).head<2>().norm() > 0.04f && cube.z() < 0.03f)
          closed_beside = true;
      } while (!r.terminated && !r.truncated);
      missed += closed_beside ? 1 : 0;
      successes += r.info.success ? 1 : 0;
    }
    INFO(name << ": missed " << missed << ", succeeded " << successes << " of " << episodes);
    // A stack episode may miss differently: a finger that lands on the other cube keeps the
    // effector up, so the fingers never shut down beside the first one.
    CHECK(missed >= episodes - 2);
    CHECK(successes >= 17);
  }
  auto push = make_env(default_env_config("push"));
  ManipulationExpert pusher(*push);
  CHECK_THROWS_WITH(pusher.miss_first_grasp(Eigen::Vector2f(0.05f, 0.0f)),
                    Catch::Matchers::Contains("only a task that grasps a cube (pick_and_place, stack) has a grasp to miss"));
}

TEST_CASE("redraw_unmoved: new places for the cubes not moved yet and the goal not reached, the rest kept, the expert "
          "still stacks",
          "[envs][manipulation][redraw]") {
  auto env = make_env(default_env_config("stack"));
  auto& m = dynamic_cast<ManipulationEnv&>(*env);
  ManipulationExpert expert(*env);
  int successes = 0, held_kept = 0, goal_kept = 0, redrawn = 0;
  const int episodes = 20;
  for (int e = 0; e < episodes; ++e) {
    // The expert's episode from this seed, then the same again to a step along it (the first to
    // the last): before the first grasp, the first cube held, on its goal, the second one held.
    int length = 0;
    for (bool ended = (env->reset(static_cast<std::uint64_t>(3000 + e)), expert.reset(), false); !ended; ++length) {
      const StepResult r = env->step(expert.act());
      ended = r.terminated || r.truncated;
    }
    Observation obs = env->reset(static_cast<std::uint64_t>(3000 + e));
    expert.reset();
    const std::vector<Eigen::Vector3f> start = {m.cube_position(0), m.cube_position(1)};
    for (int t = 0; t < e * (length - 1) / episodes; ++t) obs = env->step(expert.act()).observation;
    const std::vector<Eigen::Vector3f> before = {m.cube_position(0), m.cube_position(1)};
    const std::vector<Eigen::Vector3f> goals = m.goals();
    bool reached = false;
    for (int k = 0; k < 2; ++k) reached = reached || (before[k] - goals[k]).norm() < 0.05f;
    Rng rng(static_cast<std::uint64_t>(e));
    const bool moved = m.redraw_unmoved(rng, observation_out(obs));
    bool any_unmoved = false;
    for (int k = 0; k < 2; ++k) any_unmoved = any_unmoved || (before[k] - start[k]).norm() <= 1e-3f;
    CHECK(moved == (any_unmoved || !reached));  // nothing left to draw only once both cubes moved and the goal is met
    const Eigen::Vector3f ee = m.world().ee_position();
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3f now = m.cube_position(k);
      INFO("episode " << e << ", cube " << k);
      if ((before[k] - start[k]).norm() > 1e-3f) {
        CHECK(now == before[k]);  // moved by the expert: it stays (in the gripper, on its goal)
        held_kept += k == 0;
      } else {
        CHECK((now - before[k]).norm() > 1e-3f);  // a new place, clear of the effector and the other cube
        CHECK((now - ee).head<2>().norm() >= 0.1f);
        CHECK((now - m.cube_position(1 - k)).head<2>().norm() >= 0.06f - 1e-6f);
        CHECK(now.z() == Approx(TaskArea::cube_size / 2).margin(1e-3));
      }
      CHECK(obs.values.segment<3>(7 + 16 * k) == now);  // the observation is the new state's
    }
    CHECK((m.goals() == goals) == reached);
    CHECK(obs.values.tail<6>().head<3>() == m.goals()[0]);
    goal_kept += reached;
    redrawn += moved;
    StepResult r;
    do r = env->step(expert.act());
    while (!r.terminated && !r.truncated);
    successes += r.info.success;
  }
  INFO("succeeded " << successes << ", first cube kept " << held_kept << ", goal kept " << goal_kept << ", redrawn "
                    << redrawn << " of " << episodes);
  CHECK(held_kept >= 5);
  CHECK(goal_kept >= 3);
  CHECK(redrawn >= episodes / 2);
  CHECK(successes >= episodes - 3);

  // After load_state nothing counts as unmoved: only the goal can be drawn again.
  env->reset(5);
  const std::string saved = m.save_state();
  m.load_state(saved, "state");
  const Eigen::Vector3f cube = m.cube_position(0);
  Observation obs = env->reset(5);
  m.load_state(saved, "state");
  Rng rng(1);
  m.redraw_unmoved(rng, observation_out(obs));
  CHECK(m.cube_position(0) == cube);
}

TEST_CASE("The scripted expert solves every manipulation task with pybullet_data's Panda", "[envs][manipulation][expert][pybullet_data]") {
  if (pybullet_data().empty()) {
    WARN("skipped: pybullet_data not found");
    return;
  }
  // Measured on seeds 1000-1199 (AMD EPYC Zen 5, 2026-12-02): reach_goal 200, push 195, pick_and_place
  // 199, stack 196 of 200. The floors leave a few episodes of margin (another CPU rounds differently
  // and a grasp is chaotic). The Panda's stack needs stack's 100 steps (panda-gym's): the drive keeps
  // the URDF's joint speed limits, so its carries make 2-3 cm per step where the JAKA's make 5, and
  // in 50 steps it stacked in 72 episodes of 200.
  const std::map<std::string, int> floor = {{"reach_goal", 190}, {"push", 185}, {"pick_and_place", 185}, {"stack", 185}};
  for (const char* name : kTasks) {
    const ExpertRun run = run_expert(panda_config(name), 200);
    INFO(name << ": " << run.successes << " of " << run.episodes);
    CHECK(run.successes >= floor.at(name));
  }
}

TEST_CASE("A cube held in the air for 5 s slips less than 5 mm", "[envs][manipulation][grasp]") {
  for (int substeps : {10, 4}) {
    EnvConfig c = default_env_config("pick_and_place");
    use_substeps(c, substeps);
    c.get<ManipulationOptions>().distance_threshold = 0.001;  // no success (it would end the episode)
    c.max_steps = 400;
    auto env = make_env(c);
    auto& m = dynamic_cast<ManipulationEnv&>(*env);
    ManipulationExpert expert(*env);
    env->reset(11);
    expert.reset();
    // Grasp and lift 10 cm: the expert until the cube is held, then straight up.
    int steps = 0;
    while (m.finger_opening() > TaskArea::cube_size + 0.006f || m.cube_position(0).z() < 0.019f) {
      env->step(expert.act());
      REQUIRE(++steps < 60);
    }
    Eigen::VectorXf up(4);
    up << 0.0f, 0.0f, 0.5f, -1.0f;
    for (int t = 0; t < 10; ++t) env->step(Action::continuous(up));
    const float lifted = m.cube_position(0).z();
    REQUIRE(lifted > 0.09f);
    const Eigen::Vector3f held_at = m.cube_position(0) - m.world().ee_position();
    Eigen::VectorXf hold(4);
    hold << 0.0f, 0.0f, 0.0f, -1.0f;
    for (int t = 0; t < 125; ++t) env->step(Action::continuous(hold));  // 125 x 40 ms = 5 s
    const Eigen::Vector3f slip = (m.cube_position(0) - m.world().ee_position()) - held_at;
    INFO(substeps << " substeps: slip " << slip.norm() * 1000 << " mm");
    CHECK(slip.norm() < 0.005f);
  }
}

// With 4 physics steps of 10 ms (the same 40 ms per env step) the drive's gain and the solver
// follow the step and the expert still grasps, on both arms. Measured on seeds 1000-1199 (AMD EPYC
// Zen 5, 2026-12-02), JAKA / Panda of 200: push 199 / 198, pick_and_place 198 / 200, stack 194 / 196.
TEST_CASE("substeps: fewer, longer physics steps keep the expert's grasp", "[envs][manipulation][expert]") {
  for (const char* name : {"push", "pick_and_place", "stack"}) {
    EnvConfig jaka = default_env_config(name);
    use_substeps(jaka, 4);
    const ExpertRun run = run_expert(jaka, 100);
    INFO("JAKA " << name << ": " << run.successes << " of " << run.episodes);
    CHECK(run.successes >= 95);
    if (pybullet_data().empty()) continue;
    EnvConfig panda = panda_config(name);
    use_substeps(panda, 4);
    const ExpertRun panda_run = run_expert(panda, 100);
    INFO("Panda " << name << ": " << panda_run.successes << " of " << panda_run.episodes);
    CHECK(panda_run.successes >= 93);
  }
}

TEST_CASE("The solver follows the physics step: 10 iterations up to 4 ms, the fingers' rows solved directly beyond",
          "[envs][manipulation]") {
  auto settings = [](int substeps) {
    EnvConfig c = default_env_config("push");
    use_substeps(c, substeps);
    auto env = make_env(c);
    return dynamic_cast<ManipulationEnv&>(*env).world().world().settings();
  };
  const WorldSettings by_default = settings(10), long_steps = settings(4);
  CHECK(by_default.solver_iterations == 10);
  CHECK(by_default.solver_residual_threshold == 0.0);
  CHECK_FALSE(by_default.joint_block_solve);
  CHECK(long_steps.solver_iterations == 40);
  CHECK(long_steps.solver_residual_threshold > 0.0);
  CHECK(long_steps.joint_block_solve);
  CHECK(long_steps.joint_row_warm_start == 1.0);
  CHECK(by_default.mass_matrix_responses);
}

TEST_CASE("Manipulation envs save and load their state exactly", "[envs][manipulation][state]") {
  for (const char* name : kTasks) {
    INFO(name);
    auto a = make_env(default_env_config(name));
    auto b = make_env(default_env_config(name));
    ManipulationExpert expert(*a);
    a->reset(5);
    expert.reset();
    for (int t = 0; t < 12; ++t) a->step(expert.act());
    auto& sa = dynamic_cast<EnvState&>(*a);
    auto& sb = dynamic_cast<EnvState&>(*b);
    sa.drop_caches();
    sb.load_state(sa.save_state(), "test");
    for (int t = 0; t < 15; ++t) {
      const Action act = expert.act();
      const StepResult ra = a->step(act);
      const StepResult rb = b->step(act);
      REQUIRE(ra.observation.values == rb.observation.values);
      REQUIRE(ra.reward == rb.reward);
    }
    CHECK_THROWS_WITH(sb.load_state("nonsense", "bad.bin"), Catch::Contains("bad.bin"));
  }
}

TEST_CASE("raw_pixels: the camera image with the goals beside it, the episode as with ground truth", "[envs][manipulation][pixels]") {
  for (const char* name : {"push", "stack"}) {
    for (const char* channels : {"rgb", "depth"}) {
      INFO(name << ", " << channels);
      const EnvConfig truth = default_env_config(name);
      EnvConfig config = truth;
      config.observation = ObservationMode::RawPixels;
      config.image_width = 32;
      config.image_height = 24;
      config.image_channels = channels;
      auto pixels = make_env(config), vectors = make_env(truth);
      const Spec& spec = pixels->spec();
      const GoalLayout& g = spec.goal;
      const int image = std::string(channels) == "rgb" ? 0 : 32 * 24;  // a Float32 image's values come first
      CHECK(spec.observation.vector_size == 2 * g.goal_size());
      CHECK(g.observation == image);
      CHECK(g.points == vectors->spec().goal.points);
      const GoalLayout& t = vectors->spec().goal;
      // The same physics: the expert's episode gives the same rewards and goals in both.
      ManipulationExpert expert(*vectors);
      Observation p = pixels->reset(21);
      Observation v = vectors->reset(21);
      expert.reset();
      std::vector<std::uint8_t> first = p.pixels;
      bool image_changed = false;
      for (int step = 0; step < spec.max_episode_steps; ++step) {
        REQUIRE(p.values.size() == image + 2 * g.goal_size());
        CHECK(p.values.segment(g.achieved_offset(), 2 * g.goal_size()) == v.values.segment(t.achieved_offset(), 2 * t.goal_size()));
        const Action a = expert.act();
        const StepResult rp = pixels->step(a), rv = vectors->step(a);
        REQUIRE(rp.reward == rv.reward);
        REQUIRE(rp.terminated == rv.terminated);
        REQUIRE(rp.info.success == rv.info.success);
        p = rp.observation;
        v = rv.observation;
        image_changed = image_changed || (image == 0 ? p.pixels != first : false);
        if (rv.terminated || rv.truncated) break;
      }
      CHECK(v.values.segment(t.achieved_offset(), t.goal_size()) == p.values.segment(g.achieved_offset(), g.goal_size()));
      if (image == 0) {
        CHECK(image_changed);  // the arm and the cube move in the picture
        CHECK(*std::max_element(p.pixels.begin(), p.pixels.end()) > *std::min_element(p.pixels.begin(), p.pixels.end()));
      }
    }
  }
}

TEST_CASE("control joints: one action value per arm joint moves that joint's target, the joints are observed",
          "[envs][manipulation][joints]") {
  EnvConfig c = default_env_config("pick_and_place");
  c.get<ManipulationOptions>().control = ArmControl::Joints;
  auto env = make_env(c);
  auto& m = dynamic_cast<ManipulationEnv&>(*env);
  const std::vector<int>& arm = m.world().chain_dofs();
  REQUIRE(arm.size() == 6);  // the JAKA's joints; the fingers are not on the IK chain
  const Spec& spec = env->spec();
  CHECK(spec.action.dim() == 7);  // six joints, then the fingers
  const auto [at, size] = spec.observation.part("joint_positions");
  CHECK(size == 6);
  CHECK(at == spec.observation.part("finger_opening").first + 1);
  CHECK(spec.goal.observation == 7 + 6 + 16);
  const float step = m.joint_step();
  CHECK(step == Approx(0.2));
  Observation o = env->reset(4);
  for (int k = 0; k < 6; ++k) CHECK(o.values[at + k] == m.world().robot().joint_position(arm[static_cast<size_t>(k)]));
  for (int k = 0; k < 6; ++k) {
    INFO("joint " << k);
    Eigen::VectorXf q(6);
    for (int i = 0; i < 6; ++i) q[i] = m.world().robot().joint_position(arm[static_cast<size_t>(i)]);
    Eigen::VectorXf a = Eigen::VectorXf::Zero(7);
    a[k] = k % 2 ? -0.25f : 0.25f;
    a[6] = 1.0f;
    o = env->step(Action::continuous(a)).observation;
    const Eigen::VectorXf targets = m.world().robot().position_targets();
    for (int i = 0; i < 6; ++i)
      CHECK(targets[arm[static_cast<size_t>(i)]] == Approx(q[i] + (i == k ? a[k] * step : 0.0f)).margin(1e-6));
    for (int i = 0; i < 6; ++i) CHECK(o.values[at + i] == m.world().robot().joint_position(arm[static_cast<size_t>(i)]));
  }
  CHECK_THROWS_WITH(env->step(Action::continuous(Eigen::VectorXf::Zero(4))),
                    Catch::Contains("expected an action of 7 values (6 joint moves, fingers)"));
  c = default_env_config("push");  // fingers closed: the joints alone
  c.get<ManipulationOptions>().control = ArmControl::Joints;
  CHECK(make_env(c)->spec().action.dim() == 6);
}

TEST_CASE("is_discrete: reach_goal's and push's Discrete(6) moves are the Box moves of one unit along an axis",
          "[envs][manipulation][discrete]") {
  for (const char* name : {"reach_goal", "push"}) {
    INFO(name);
    EnvConfig c = default_env_config(name);
    c.is_discrete = true;
    auto discrete = make_env(c);
    auto box = make_env(default_env_config(name));
    CHECK(discrete->spec().action.discrete);
    CHECK(discrete->spec().action.n == 6);
    CHECK(discrete->spec().goal.active());
    for (int k = 0; k < 6; ++k) {
      INFO("action " << k);
      const Observation a = discrete->reset(7), b = box->reset(7);
      REQUIRE(a.values == b.values);
      Eigen::VectorXf unit = Eigen::VectorXf::Zero(3);
      unit[k / 2] = k % 2 ? 1.0f : -1.0f;  // -x, +x, -y, +y, -z, +z
      const StepResult sd = discrete->step(Action::discrete(k)), sb = box->step(Action::continuous(unit));
      CHECK(sd.observation.values == sb.observation.values);
      CHECK(sd.reward == sb.reward);
      CHECK((dynamic_cast<ManipulationEnv&>(*discrete).world().ee_position() - dynamic_cast<ManipulationEnv&>(*box).world().ee_position()).norm() == 0.0f);
    }
    CHECK_THROWS_WITH(discrete->step(Action::discrete(6)), Catch::Contains("discrete action must be 0..5"));
    CHECK_THROWS_WITH(ManipulationExpert(*discrete), Catch::Contains("expected env.is_discrete false"));
  }
}

// Measured on seeds 1000-1199 (Intel Xeon, 2026-11-29), joint_step 0.2: reach_goal 200, push 196,
// pick_and_place 200, stack 199 of 200 (0.05 rad, panda-gym's step: push 179, too slow for 50 steps;
// stack 195). The test runs the first 100 seeds (CI's time).
TEST_CASE("The scripted expert solves every manipulation task in joint control too", "[envs][manipulation][expert][joints]") {
  for (const char* name : kTasks) {
    EnvConfig c = default_env_config(name);
    c.get<ManipulationOptions>().control = ArmControl::Joints;
    const ExpertRun run = run_expert(c, 100);
    INFO(name << ": " << run.successes << " of " << run.episodes);
    CHECK(run.successes >= 95);  // >= 95 %
  }
}

TEST_CASE("Manipulation options that cannot work are one clear error naming the key", "[envs][manipulation][errors]") {
  EnvConfig c = default_env_config("pick_and_place");
  c.get<ManipulationOptions>().finger_joints = {"finger_left_joint", "finger_middle_joint"};
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("jaka_zu7_gripper.urdf: env.finger_joints: \"finger_middle_joint\" is not "
                                                 "a joint of the robot"));
  c = default_env_config("pick_and_place");
  c.get<ManipulationOptions>().finger_joints = {"joint_6"};
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("env.finger_joints: \"joint_6\" is not a prismatic joint"));
  c = default_env_config("pick_and_place");
  c.get<ManipulationOptions>().finger_joints = {"finger_left_joint"};  // 42.5 mm: cannot open round a 4 cm cube
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("env.finger_joints: the fingers open 0.0425 m at most"));
  c = default_env_config("push");
  c.get<ManipulationOptions>().goal_range = 0.5;
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("env.goal_range: the goals") && Catch::Contains("workspace box"));
  c = default_env_config("pick_and_place");
  c.get<ManipulationOptions>().goal_height = 0.6;
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("env.goal_height"));
  c = default_env_config("stack");
  c.get<ArmOptions>().home_pose = {0.0, 1.0};
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("jaka_zu7_gripper.urdf: env.home_pose: expected 6 values"));
  c = default_env_config("pick_and_place");
  c.is_discrete = true;
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("env.is_discrete: pick_and_place with the fingers to move has Box actions only"));
  c = default_env_config("push");
  c.is_discrete = true;
  c.get<ManipulationOptions>().control = ArmControl::Joints;
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("env.is_discrete: push with control \"joints\" has Box actions only"));
  auto env = make_env(default_env_config("pick_and_place"));
  env->reset(1);
  CHECK_THROWS_WITH(env->step(Action::continuous(Eigen::VectorXf::Zero(3))), Catch::Contains("expected an action of 4 values"));
  const auto read = [](const nlohmann::json& json) {
    ConfigReader r(json, "x.json", "env");
    return read_env_config(r);
  };
  CHECK_THROWS_WITH(read({{"name", "push"}, {"control", "joint"}}),
                    Catch::Contains("x.json: env.control: expected one of \"effector\", \"joints\""));
  CHECK_THROWS_WITH(read({{"name", "push"}, {"joint_step", 0}}), Catch::Contains("x.json: env.joint_step: expected a number"));
}

TEST_CASE("Manipulation: the docs' pictures of the Panda's tasks", "[.demo]") {
  REQUIRE_FALSE(pybullet_data().empty());
  for (const char* name : kTasks) {
    EnvConfig c = panda_config(name);
    c.render_mode = RenderMode::RgbArray;
    c.render_width = 320;
    c.render_height = 240;
    auto env = make_env(c);
    env->reset(3);
    Image frame;
    REQUIRE(env->render(frame));
    write_png(repo_root() + "/docs/manipulation_panda_" + name + ".png", frame.width, frame.height, 3, frame.rgb.data());
  }
}

TEST_CASE("Manipulation envs are driven by hand through RobotControl, the gripper by its joints", "[envs][manipulation][robot_control]") {
  auto env = make_env(default_env_config("pick_and_place"));
  auto& control = dynamic_cast<RobotControl&>(*env);
  auto& m = dynamic_cast<ManipulationEnv&>(*env);
  const RobotInfo& info = control.robot_info();
  CHECK(info.robot == "jaka_zu7_gripper");
  CHECK(info.effector_link == "gripper_tcp");
  REQUIRE(info.joints.size() == 8);  // six arm joints and the two fingers
  CHECK(info.joints[6].kind == JointKind::Prismatic);
  REQUIRE(info.cameras.size() == 1);
  CHECK(info.cameras[0].name == "scene");
  env->reset(4);
  const Eigen::Quaternionf down = control.robot_state().effector_orientation;
  CHECK(control.robot_state().target == m.goals().front());
  // The effector to a point over the cube by IK, the gripper's orientation held, one env step a call.
  const Eigen::Vector3f over = m.cube_position(0) + Eigen::Vector3f(0.0f, 0.0f, 0.06f);
  for (int t = 0; t < 15; ++t) control.move_effector(over);
  const RobotSnapshot s = control.robot_state();
  CHECK((s.effector_position - over).norm() < 0.005f);
  CHECK(s.effector_orientation.angularDistance(down) < 0.02f);
  CHECK(s.steps == 15);
  // The fingers by their joint targets: closed.
  Eigen::VectorXf q = s.joint_targets;
  q[6] = q[7] = 0.0f;
  for (int t = 0; t < 10; ++t) control.set_joint_targets(q);
  CHECK(m.finger_opening() < 0.002f);
  CHECK_THROWS_WITH(control.set_joint_targets(Eigen::VectorXf::Zero(6)), Catch::Contains("expected 8 joint targets"));
  Image image;
  control.camera_image(0, 32, 24, image);
  CHECK(image.width == 32);
  CHECK(image.rgb.size() == 32u * 24u * 3u);
}
