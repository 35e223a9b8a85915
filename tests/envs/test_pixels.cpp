#include <catch2/catch.hpp>
#include <set>

#include "rdsim/core/error.hpp"
#include "rdsim/envs/reaching/jaka_button.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/envs/robot_scene.hpp"
#include "rdsim/render/camera.hpp"
#include "rdsim/render/renderer.hpp"

using rdsim::EnvConfig;
using rdsim::ObsType;

namespace {

EnvConfig pixel_config(bool random_target = false) {
  EnvConfig c = rdsim::default_env_config("jaka_button");
  c.observation = rdsim::ObservationMode::RawPixels;
  c.get<rdsim::ReachOptions>().random_target = random_target;
  return c;
}

// Mean image position (x, y) of the button's red top in a 3-channel-per-view image; count = 0 when absent.
struct RedBlob {
  int count = 0;
  double x = 0, y = 0;
};

RedBlob red_blob(const std::vector<std::uint8_t>& pixels, int width, int height, int channels) {
  RedBlob b;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::uint8_t* p = pixels.data() + (y * width + x) * channels;
      if (p[0] > 120 && p[1] < 60 && p[2] < 60) {
        ++b.count;
        b.x += x;
        b.y += y;
      }
    }
  if (b.count > 0) {
    b.x /= b.count;
    b.y /= b.count;
  }
  return b;
}

}  // namespace

TEST_CASE("jaka_button raw pixels: UInt8 images of the configured size, 6 channels with two views", "[pixels]") {
  rdsim::JakaButton env(pixel_config());
  const rdsim::ObservationSpace& space = env.spec().observation;
  CHECK(space.type == ObsType::UInt8);
  CHECK(space.shape == std::vector<int>{64, 64, 3});
  const rdsim::Observation obs = env.reset(0);
  CHECK(obs.pixels.size() == 64u * 64u * 3u);
  CHECK(obs.values.size() == 0);
  // Not a blank frame: the scene has several colours.
  CHECK(*std::max_element(obs.pixels.begin(), obs.pixels.end()) - *std::min_element(obs.pixels.begin(), obs.pixels.end()) > 100);
  CHECK(env.step(rdsim::Action::discrete(1)).observation.pixels.size() == obs.pixels.size());

  EnvConfig two = pixel_config();
  two.multi_view = true;
  two.image_width = 48;
  two.image_height = 32;
  rdsim::JakaButton stacked(two);
  CHECK(stacked.spec().observation.shape == std::vector<int>{32, 48, 6});
  const rdsim::Observation o2 = stacked.reset(0);
  REQUIRE(o2.pixels.size() == 32u * 48u * 6u);
  // The two cameras see different things.
  bool differ = false;
  for (size_t p = 0; p < 32u * 48u && !differ; ++p)
    for (size_t c = 0; c < 3; ++c) differ = differ || o2.pixels[6 * p + c] != o2.pixels[6 * p + 3 + c];
  CHECK(differ);

  EnvConfig bad = pixel_config();
  bad.image_width = 0;
  CHECK_THROWS_WITH(rdsim::JakaButton(bad), Catch::Contains("env.image_width"));
  const auto& registry = rdsim::env_registry();
  const auto entry = std::find_if(registry.begin(), registry.end(), [](const auto& e) { return e.name == "jaka_button"; });
  REQUIRE(entry != registry.end());
  CHECK(entry->supports_pixels);
}

TEST_CASE("jaka_button raw pixels: the button is visible and moves with a random target", "[pixels]") {
  rdsim::JakaButton env(pixel_config(true));
  RedBlob first;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    INFO("seed " << seed);
    const rdsim::Observation obs = env.reset(seed);
    const RedBlob blob = red_blob(obs.pixels, 64, 64, 3);
    CHECK(blob.count >= 2);  // visible at 64x64
    if (seed == 1) first = blob;
    else CHECK(std::abs(blob.x - first.x) + std::abs(blob.y - first.y) > 0.5);
  }
}

TEST_CASE("raw pixels are deterministic, and two envs render independently in one process", "[pixels]") {
  EnvConfig config = pixel_config(true);
  config.multi_view = true;
  rdsim::JakaButton a(config), b(config);
  std::vector<std::vector<std::uint8_t>> alone;
  alone.push_back(a.reset(3).pixels);
  for (int t = 0; t < 4; ++t) alone.push_back(a.step(rdsim::Action::discrete(t % 6)).observation.pixels);
  // Interleaved with another env (different seed) drawing between every frame.
  rdsim::JakaButton c(config);
  CHECK(b.reset(3).pixels == alone[0]);
  const std::vector<std::uint8_t> other = c.reset(4).pixels;
  CHECK(other != alone[0]);
  for (int t = 0; t < 4; ++t) {
    CHECK(b.step(rdsim::Action::discrete(t % 6)).observation.pixels == alone[static_cast<size_t>(t + 1)]);
    c.step(rdsim::Action::discrete(5));
  }
  CHECK(alone[4] != alone[0]);  // the arm moved
}

TEST_CASE("RobotScene: one segmentation id per robot link and static body, each seen where it is visible",
          "[pixels][segmentation]") {
  EnvConfig config = rdsim::default_env_config("jaka_button");
  rdsim::JakaButton env(config);
  env.reset(0);
  const rdsim::ReachTask& task = env.task();
  rdsim::RobotScene scene;
  rdsim::add_task_bodies(scene, task);
  const rdsim::RobotModel& robot = task.robot_model();
  const std::size_t statics = task.spec().statics.size();
  REQUIRE(scene.segments.size() == 1 + robot.links.size() + statics);
  CHECK(scene.segments[0] == "background");
  for (std::size_t l = 0; l < robot.links.size(); ++l) CHECK(scene.segments[1 + l] == robot.name + "/" + robot.links[l].name);
  for (std::size_t i = 0; i < statics; ++i)
    CHECK(scene.segments[1 + robot.links.size() + i] == task.static_model(static_cast<int>(i)).name);
  // Each item carries its link's or body's id.
  for (const rdsim::ScenePart& part : scene.parts) {
    const int id = scene.scene.items[static_cast<std::size_t>(part.item)].segment;
    if (part.link >= 0) CHECK(id == 1 + part.link);
    else CHECK(id > static_cast<int>(robot.links.size()));
  }
  // From the main camera, every static body (table, button) and the arm's links show their ids.
  const int w = 160, h = 120;
  auto renderer = rdsim::make_renderer("osmesa", w, h);
  std::vector<std::uint8_t> ids(static_cast<std::size_t>(w * h));
  renderer->render(scene.scene, rdsim::make_orbit_camera(rdsim::reach_main_view(), w, h),
                   rdsim::RenderTargets{.segmentation = ids.data()});
  const std::set<int> seen(ids.begin(), ids.end());
  CHECK(*seen.rbegin() < static_cast<int>(scene.segments.size()));
  for (std::size_t i = 0; i < statics; ++i) {
    INFO(scene.segments[1 + robot.links.size() + i]);
    CHECK(seen.count(static_cast<int>(1 + robot.links.size() + i)) == 1);
  }
  int links_seen = 0;
  for (std::size_t l = 0; l < robot.links.size(); ++l)
    if (!robot.links[l].visuals.empty()) links_seen += static_cast<int>(seen.count(static_cast<int>(1 + l)));
  CHECK(links_seen >= 5);  // the arm's base and links in view
}

TEST_CASE("RobotScene: one item per URDF visual, poses follow the robot", "[pixels]") {
  EnvConfig config = rdsim::default_env_config("jaka_button");
  rdsim::JakaButton env(config);
  env.reset(0);
  const rdsim::ReachTask& task = env.task();
  rdsim::RobotScene scene;
  rdsim::add_robot(scene, task.robot());
  size_t visuals = 0;
  for (const auto& link : task.robot_model().links) visuals += link.visuals.size();
  CHECK(scene.scene.items.size() == visuals);
  const size_t robot_items = visuals;
  rdsim::add_static_body(scene, task.world(), task.static_body(rdsim::JakaButton::button_index),
                         task.static_model(rdsim::JakaButton::button_index));
  REQUIRE(scene.scene.items.size() > robot_items);
  // The button's top sits at the target (its frame plus the 3 cm offset), within the shape's height.
  const Eigen::Vector3f button = scene.scene.items.back().pose.translation();
  CHECK((button.head<2>() - task.target().head<2>()).norm() < 1e-4f);

  const Eigen::Isometry3f before = scene.scene.items[robot_items - 1].pose;
  for (int t = 0; t < 10; ++t) env.step(rdsim::Action::discrete(5));  // +z moves
  rdsim::update_poses(scene, env.task().world());
  const Eigen::Isometry3f after = scene.scene.items[robot_items - 1].pose;
  CHECK((after.translation() - before.translation()).norm() > 0.02f);
  const int last_link = scene.parts[robot_items - 1].link;
  CHECK(after.isApprox(task.robot().link_pose(last_link) * scene.parts[robot_items - 1].offset, 1e-5f));
}

TEST_CASE("inmoov_tomato raw pixels: the tomatoes are visible, the target choice is deterministic", "[pixels]") {
  EnvConfig config = rdsim::default_env_config("inmoov_tomato");
  config.observation = rdsim::ObservationMode::RawPixels;
  config.get<rdsim::ReachOptions>().random_target = true;
  const auto env = rdsim::make_env(config);
  CHECK(env->spec().observation.type == ObsType::UInt8);
  CHECK(env->spec().observation.shape == std::vector<int>{64, 64, 3});
  const std::vector<std::uint8_t> first = env->reset(1).pixels;
  CHECK(red_blob(first, 64, 64, 3).count >= 6);  // six red tomatoes, a few pixels each
  const auto again = rdsim::make_env(config);
  CHECK(again->reset(1).pixels == first);
  CHECK(env->step(rdsim::Action::discrete(5)).observation.pixels != first);  // the palm moved
}

TEST_CASE("jaka_obstacle raw pixels: button and column in view, two views stack", "[pixels]") {
  EnvConfig config = rdsim::default_env_config("jaka_obstacle");
  config.observation = rdsim::ObservationMode::RawPixels;
  config.get<rdsim::ReachOptions>().random_target = true;
  config.multi_view = true;
  const auto env = rdsim::make_env(config);
  REQUIRE(env->spec().observation.shape == std::vector<int>{64, 64, 6});
  for (std::uint64_t seed : {1, 2, 3}) {
    INFO("seed " << seed);
    const std::vector<std::uint8_t> px = env->reset(seed).pixels;
    std::vector<std::uint8_t> view(64 * 64 * 3);
    for (int v = 0; v < 2; ++v) {
      INFO("view " << v + 1);
      for (size_t p = 0; p < 64u * 64u; ++p)
        for (size_t c = 0; c < 3; ++c) view[3 * p + c] = px[6 * p + 3 * static_cast<size_t>(v) + c];
      CHECK(red_blob(view, 64, 64, 3).count >= 2);  // the button's red top
      // The orange column (its URDF colour: strong red, medium green, low blue).
      int column = 0;
      for (size_t p = 0; p < 64u * 64u; ++p)
        column += view[3 * p] > 150 && view[3 * p + 1] > 50 && view[3 * p + 1] < 120 && view[3 * p + 2] < 40;
      CHECK(column >= 10);
    }
  }
}

TEST_CASE("image_channels: Float32 colour, depth and segmentation from one drawing, as the renderer gives them",
          "[pixels][segmentation]") {
  EnvConfig colour = pixel_config(true);
  EnvConfig all = colour;
  all.image_channels = "rgb_depth_segmentation";
  rdsim::JakaButton a(colour), b(all);
  const rdsim::ObservationSpace& space = b.spec().observation;
  CHECK(space.type == ObsType::Float32);
  REQUIRE(space.shape == std::vector<int>{64, 64, 5});
  const rdsim::Camera camera = rdsim::make_orbit_camera(rdsim::reach_main_view(), 64, 64);
  REQUIRE(space.high.size() == 64 * 64 * 5);
  CHECK(space.low.isZero());
  CHECK(space.high.head<5>() == Eigen::Vector<float, 5>(1.0f, 1.0f, 1.0f, camera.zfar, 255.0f));
  CHECK(space.high.tail<5>() == space.high.head<5>());

  const std::vector<std::uint8_t> rgb = a.reset(5).pixels;
  const Eigen::VectorXf stacked = b.reset(5).values;
  REQUIRE(stacked.size() == 64 * 64 * 5);
  // The same scene drawn straight by a renderer: its depth and ids are what the observation holds.
  rdsim::RobotScene scene;
  rdsim::add_task_bodies(scene, b.task());
  auto renderer = rdsim::make_renderer("osmesa", 64, 64);
  std::vector<float> depth(64 * 64);
  std::vector<std::uint8_t> ids(64 * 64);
  renderer->render(scene.scene, camera, rdsim::RenderTargets{.depth = depth.data(), .segmentation = ids.data()});
  int mismatches = 0, background = 0, mc = 0, md = 0, ms = 0;
  for (int p = 0; p < 64 * 64; ++p) {
    // Colour as the networks scale UInt8 images (times 1/255, not divided by 255: they can differ in the last bit).
    for (int k = 0; k < 3; ++k) mc += stacked[5 * p + k] != static_cast<float>(rgb[3 * p + k]) * (1.0f / 255.0f);
    md += stacked[5 * p + 3] != depth[static_cast<size_t>(p)];
    ms += stacked[5 * p + 4] != static_cast<float>(ids[static_cast<size_t>(p)]);
    if (ids[static_cast<size_t>(p)] == 0) {
      ++background;
      CHECK(stacked[5 * p + 3] == camera.zfar);  // nothing drawn: the far plane
    } else {
      CHECK(stacked[5 * p + 3] > 0.1f);  // the table and robot lie a metre or two away
      CHECK(stacked[5 * p + 3] < 5.0f);
    }
  }
  CHECK(mc == 0);
  CHECK(md == 0);
  CHECK(ms == 0);
  CHECK(background < 64 * 64);
  std::set<int> id_seen;
  for (int p = 0; p < 64 * 64; ++p) id_seen.insert(static_cast<int>(stacked[5 * p + 4]));
  CHECK(id_seen.size() >= 4);  // background, table, button and arm links
  CHECK(*id_seen.rbegin() < static_cast<int>(scene.segments.size()));

  // One channel alone, and two cameras (the first camera's channels first).
  EnvConfig depth_only = colour;
  depth_only.image_channels = "depth";
  rdsim::JakaButton d(depth_only);
  CHECK(d.spec().observation.shape == std::vector<int>{64, 64, 1});
  const Eigen::VectorXf dv = d.reset(5).values;
  for (int p = 0; p < 64 * 64; ++p) mismatches += dv[p] != stacked[5 * p + 3];
  CHECK(mismatches == 0);
  EnvConfig two = colour;
  two.image_channels = "rgb_depth";
  two.multi_view = true;
  rdsim::JakaButton t(two);
  REQUIRE(t.spec().observation.shape == std::vector<int>{64, 64, 8});
  const Eigen::VectorXf tv = t.reset(5).values;
  bool second_differs = false;
  for (int p = 0; p < 64 * 64; ++p) {
    for (int k = 0; k < 4; ++k) mismatches += tv[8 * p + k] != stacked[5 * p + k];
    second_differs = second_differs || tv[8 * p + 7] != tv[8 * p + 3];
  }
  CHECK(mismatches == 0);
  CHECK(second_differs);
  // Steps give the same channels as a fresh drawing (the observation is rendered every step).
  const rdsim::StepResult r = b.step(rdsim::Action::discrete(5));
  CHECK(r.observation.values.size() == stacked.size());
  CHECK(r.observation.values != stacked);
}
