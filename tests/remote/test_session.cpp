// A server session without sockets: env creation from a hello, and every request checked and
// answered exactly as the local env would (bit for bit).
#include <catch2/catch.hpp>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/codec.hpp"
#include "rdsim/remote/session.hpp"

using namespace rdsim;
using namespace rdsim::remote;
using Catch::Matchers::Contains;

namespace {

Request request(const std::string& json) {
  const std::string text = json;
  const ParsedRequest p = parse_request({text});
  INFO(p.error);
  REQUIRE(p.request);
  return *p.request;
}

Request hello(const std::string& env) {
  return request(R"({"id": 1, "request": "hello", "protocol": 1, "env": )" + env + "}");
}

std::string hello_error(const std::string& env) {
  try {
    Session s(hello(env));
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("session: a hello's env config is read by the training-config code, with its messages",
          "[remote][session]") {
  // The same message a config file gets, with "hello" where the file name would be.
  const nlohmann::json bad = {{"name", "jaka_button"}, {"max_steps", 0}};
  std::string local;
  try {
    ConfigReader r(bad, "hello", "env");
    read_env_config(r);
  } catch (const Error& e) {
    local = e.what();
  }
  CHECK(hello_error(bad.dump()) == local);
  CHECK_THAT(local, Contains("hello: env.max_steps: expected an integer in [1, 1e8], got 0"));
  CHECK_THAT(hello_error(R"({"name": "pong"})"), Contains("hello: env.name: unknown environment \"pong\""));
  CHECK_THAT(hello_error(R"({"name": "cartpole", "image_width": 64})"), Contains("env.image_width: has no effect on cartpole"));
  CHECK_THAT(hello_error(R"({"name": "jaka_button", "remote": "tcp://127.0.0.1:1"})"), Contains("env.remote: unknown key"));
  CHECK_THAT(hello_error(R"({"name": "jaka_button", "urdf_root": "/etc"})"), Contains("env.urdf_root: not accepted over the link"));
  CHECK_THAT(hello_error(R"({"name": "reach", "urdf": "/etc/arm.urdf"})"), Contains("env.urdf: not accepted over the link"));
  CHECK_THAT(hello_error(R"({"name": "reach", "package_paths": ["/etc"]})"), Contains("env.package_paths: not accepted over the link"));
  CHECK_THAT(hello_error(R"({"name": "jaka_button", "render_mode": "rgb_array"})"), Contains("cameras request"));
  CHECK_THAT(hello_error(R"({"name": "jaka_button", "observation": "raw_pixels", "image_width": 4096, "image_height": 4096})"),
             Contains("larger than this server allows"));
}

TEST_CASE("session: hello reply holds the resolved env config, spec and robot", "[remote][session]") {
  Session s(hello(R"({"name": "jaka_button", "max_steps": 50})"));
  const Message m = s.hello_reply(1);
  CHECK(m.header["reply"] == "hello");
  CHECK(m.header["protocol"] == 1);
  CHECK(m.header["env"]["max_steps"] == 50);
  CHECK(m.header["env"]["action_step"] == 0.015);  // the env's published default, filled in
  const auto local = make_env(s.config());
  const Spec spec = get_spec(m);
  CHECK(spec.env_name == "jaka_button");
  CHECK(spec.observation.shape == local->spec().observation.shape);
  CHECK(spec.observation.low == local->spec().observation.low);
  CHECK(spec.max_episode_steps == 50);
  CHECK(spec.control_dt == local->spec().control_dt);
  const auto robot = get_robot_info(m);
  REQUIRE(robot);
  CHECK(robot->joints.size() == 6);
  CHECK(robot->cameras.at(0).name == "wrist");
  Session cartpole(hello(R"({"name": "cartpole"})"));
  CHECK_FALSE(get_robot_info(cartpole.hello_reply(2)));
}

TEST_CASE("session: replies equal the local env's results bit for bit", "[remote][session]") {
  for (const char* config : {R"({"name": "jaka_button", "random_target": true})", R"({"name": "cartpole"})",
                             R"({"name": "jaka_obstacle", "is_discrete": false})"}) {
    INFO(config);
    Session s(hello(config));
    const auto local = make_env(s.config());
    const Spec& spec = local->spec();
    Observation mine = local->reset(42);
    const Observation theirs = get_observation(s.handle(request(R"({"id": 2, "request": "reset", "seed": 42})")), spec);
    CHECK(theirs.values == mine.values);
    for (int t = 0; t < 120; ++t) {
      std::string action;
      Action a;
      if (spec.action.discrete) {
        a = Action::discrete(t * 7 % spec.action.n);
        action = std::to_string(a.index);
      } else {
        a = Action::continuous(Eigen::Vector3f(0.3f, -0.7f + 0.01f * t, 1.0f / 3.0f));
        action = nlohmann::json(std::vector<float>(a.values.data(), a.values.data() + 3)).dump();
      }
      const StepResult want = local->step(a);
      const StepResult got = get_step_result(s.handle(request(R"({"id": 3, "request": "step", "action": )" + action + "}")), spec);
      REQUIRE(got.observation.values == want.observation.values);
      REQUIRE(got.reward == want.reward);
      REQUIRE(got.terminated == want.terminated);
      REQUIRE(got.truncated == want.truncated);
      REQUIRE(got.info.distance == want.info.distance);
      REQUIRE(got.info.success == want.info.success);
      if (want.terminated || want.truncated) {
        local->reset();
        s.handle(request(R"({"id": 4, "request": "reset"})"));
      }
    }
  }
}

TEST_CASE("session: requests out of order or outside the spec are errors, and the session goes on",
          "[remote][session]") {
  Session s(hello(R"({"name": "jaka_button"})"));
  CHECK_THROWS_WITH(s.handle(request(R"({"id": 2, "request": "step", "action": 1})")),
                    Contains("step: the episode has not started: send reset first"));
  CHECK_THROWS_WITH(s.handle(request(R"({"id": 2, "request": "position", "position": [0.5, 0, 0.1]})")),
                    Contains("send reset first"));
  s.handle(request(R"({"id": 3, "request": "reset", "seed": 1})"));
  CHECK_THROWS_WITH(s.handle(request(R"({"id": 4, "request": "step", "action": 6})")),
                    Contains("step: action: expected an integer in 0..5 (Discrete(6))"));
  CHECK_THROWS_WITH(s.handle(request(R"({"id": 4, "request": "step", "action": [1, 0, 0]})")), Contains("0..5"));
  CHECK_THROWS_WITH(s.handle(request(R"({"id": 4, "request": "joints", "joints": [0, 0]})")),
                    Contains("expected 6 joint targets"));
  CHECK_THROWS_WITH(s.handle(request(R"({"id": 4, "request": "cameras", "width": 8, "height": 8, "cameras": ["eye"]})")),
                    Contains("no camera \"eye\" (this robot has: wrist, scene)"));
  CHECK_THROWS_WITH(s.handle(request(R"({"id": 4, "request": "cameras", "width": 8, "height": 8, "cameras": ["wrist", "wrist"]})")),
                    Contains("named twice"));
  CHECK_THROWS_WITH(s.handle(request(R"({"id": 4, "request": "hello", "protocol": 1, "env": {"name": "cartpole"}})")),
                    Contains("already has a session"));
  const Message step = s.handle(request(R"({"id": 5, "request": "step", "action": 1})"));
  CHECK(step.header["id"] == 5);
  CHECK(step.header["reply"] == "step");
  CHECK(s.steps() == 1);

  Session cartpole(hello(R"({"name": "cartpole"})"));
  cartpole.handle(request(R"({"id": 2, "request": "reset"})"));
  CHECK_THROWS_WITH(cartpole.handle(request(R"({"id": 3, "request": "state"})")), Contains("cartpole has no robot to control"));
  CHECK_THROWS_WITH(cartpole.handle(request(R"({"id": 3, "request": "step", "action": [0.5]})")), Contains("0..1"));
}

TEST_CASE("session: position, joints, state and cameras drive the robot", "[remote][session]") {
  Session s(hello(R"({"name": "jaka_button"})"));
  s.handle(request(R"({"id": 2, "request": "reset", "seed": 5})"));
  Message m;
  for (int i = 0; i < 80; ++i) m = s.handle(request(R"({"id": 3, "request": "position", "position": [0.45, -0.1, 0.15]})"));
  CHECK(m.header["reply"] == "position");
  const std::vector<float> ee = m.find("effector_position")->floats();
  CHECK(std::abs(ee[0] - 0.45f) < 0.003f);
  CHECK(std::abs(ee[1] + 0.10f) < 0.003f);
  CHECK(m.find("joint_positions")->count() == 6);
  const RobotSnapshot state = get_robot_state(s.handle(request(R"({"id": 4, "request": "state"})")), 6);
  CHECK(state.steps == 80);
  CHECK(state.effector_position == Eigen::Map<const Eigen::Vector3f>(ee.data()));
  m = s.handle(request(R"({"id": 5, "request": "cameras", "width": 40, "height": 30})"));
  const Image wrist = get_image(m, "wrist", 40, 30);
  CHECK(wrist.rgb.size() == 40u * 30u * 3u);
  m = s.handle(request(R"({"id": 6, "request": "joints", "joints": [0, 1.44, -1.85, 1.98, 1.5708, 0]})"));
  CHECK(m.header["reply"] == "joints");
}

TEST_CASE("session: a goal env's layout and reward cross the link, its steps bit for bit", "[remote][session]") {
  Session s(hello(R"({"name": "pick_and_place"})"));
  const Message m = s.hello_reply(1);
  const auto local = make_env(s.config());
  const Spec spec = get_spec(m);
  const GoalLayout& want = local->spec().goal;
  CHECK(spec.goal.observation == want.observation);
  CHECK(spec.goal.points == want.points);
  CHECK(spec.goal.distance_threshold == want.distance_threshold);
  CHECK(spec.goal.reward == want.reward);
  for (const char* reward : {"partial", "dense"}) {  // each reward type by name
    Session other(hello(std::string(R"({"name": "stack", "reward_type": ")") + reward + "\"}"));
    CHECK(to_string(get_spec(other.hello_reply(1)).goal.reward) == std::string(reward));
  }
  REQUIRE(spec.observation.parts.size() == local->spec().observation.parts.size());
  for (size_t p = 0; p < spec.observation.parts.size(); ++p) {
    CHECK(spec.observation.parts[p].name == local->spec().observation.parts[p].name);
    CHECK(spec.observation.parts[p].size == local->spec().observation.parts[p].size);
  }
  const auto robot = get_robot_info(m);  // driven by hand too: the fingers are joints
  REQUIRE(robot);
  CHECK(robot->joints.size() == 8);
  CHECK(local->reset(9).values ==
        get_observation(s.handle(request(R"({"id": 2, "request": "reset", "seed": 9})")), spec).values);
  for (int t = 0; t < 30; ++t) {
    const std::vector<float> a{0.4f, -0.2f, -1.0f + 0.05f * static_cast<float>(t), t < 15 ? 1.0f : -1.0f};
    const StepResult mine = local->step(Action::continuous(Eigen::Map<const Eigen::VectorXf>(a.data(), 4)));
    const StepResult theirs = get_step_result(
        s.handle(request(R"({"id": 3, "request": "step", "action": )" + nlohmann::json(a).dump() + "}")), spec);
    REQUIRE(theirs.observation.values == mine.observation.values);
    REQUIRE(theirs.reward == mine.reward);
    if (mine.terminated || mine.truncated) break;
  }
  // The robot state carries the other bodies (table, floor, cube, goal marker) as the env has them.
  const RobotSnapshot state = get_robot_state(s.handle(request(R"({"id": 5, "request": "state"})")), 8);
  const RobotSnapshot own = dynamic_cast<RobotControl&>(*local).robot_state();
  REQUIRE(state.bodies.size() == 4u);
  for (size_t b = 0; b < own.bodies.size(); ++b) CHECK(state.bodies[b].position == own.bodies[b].position);
  // A malformed goal layout in a reply is one clear error.
  Message bad = m;
  bad.header["spec"]["goal"]["points"] = 5;
  CHECK_THROWS_WITH(get_spec(bad), Contains("spec.goal"));
  // So are parts that do not cover the values once.
  for (const nlohmann::json& parts : {nlohmann::json::array({{"a", 5}}), nlohmann::json::array({{"a", 20}, {"a", 9}}),
                                      nlohmann::json::array({{"a", 29}, {"b", 0}}), nlohmann::json("a")}) {
    bad = m;
    bad.header["spec"]["observation"]["parts"] = parts;
    CHECK_THROWS_WITH(get_spec(bad), Contains("spec.observation.parts"));
  }
}

TEST_CASE("session: a goal env's camera images cross the link with the goals beside them", "[remote][session]") {
  for (const char* channels : {"rgb", "depth"}) {
    INFO(channels);
    Session s(hello(std::string(R"({"name": "push", "observation": "raw_pixels", "image_width": 32, "image_height": 24, )") +
                    R"("image_channels": ")" + channels + R"("})"));
    const Message m = s.hello_reply(1);
    const auto local = make_env(s.config());
    const Spec spec = get_spec(m);
    const ObservationSpace& want = local->spec().observation;
    CHECK(spec.observation.type == want.type);
    CHECK(spec.observation.shape == want.shape);
    CHECK(spec.observation.vector_size == want.vector_size);
    CHECK(spec.observation.low == want.low);
    CHECK(spec.observation.parts == want.parts);
    CHECK(spec.goal.observation == local->spec().goal.observation);
    const Observation mine = local->reset(9);
    const Observation theirs = get_observation(s.handle(request(R"({"id": 2, "request": "reset", "seed": 9})")), spec);
    CHECK(theirs.values == mine.values);
    CHECK(theirs.pixels == mine.pixels);
    for (int t = 0; t < 10; ++t) {
      const std::vector<float> a{0.4f, -0.2f, -0.5f};
      const StepResult own = local->step(Action::continuous(Eigen::Map<const Eigen::VectorXf>(a.data(), 3)));
      const StepResult got = get_step_result(
          s.handle(request(R"({"id": 3, "request": "step", "action": )" + nlohmann::json(a).dump() + "}")), spec);
      REQUIRE(got.observation.values == own.observation.values);
      REQUIRE(got.observation.pixels == own.observation.pixels);
      REQUIRE(got.reward == own.reward);
    }
    // A vector beside a flat observation, and a reply without the vector, are each one clear error.
    Message bad = m;
    bad.header["spec"]["observation"]["shape"] = {12};
    CHECK_THROWS_WITH(get_spec(bad), Contains("spec.observation"));
    Message reply = s.handle(request(R"({"id": 4, "request": "reset", "seed": 9})"));
    reply.arrays.erase(std::remove_if(reply.arrays.begin(), reply.arrays.end(),
                                      [](const ArrayFrame& f) { return f.name == "observation_vector"; }),
                       reply.arrays.end());
    CHECK_THROWS_WITH(get_observation(reply, spec), Contains("observation_vector"));
  }
}
