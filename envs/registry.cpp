#include "rdsim/envs/registry.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "rdsim/core/error.hpp"
#include "rdsim/core/suggest.hpp"
#include "rdsim/envs/classic/cartpole.hpp"
#include "rdsim/envs/pixel_view.hpp"
#include "rdsim/envs/randomization.hpp"
#include "rdsim/envs/reaching/inmoov_tomato.hpp"
#include "rdsim/envs/reaching/jaka_button.hpp"
#include "rdsim/envs/reaching/jaka_obstacle.hpp"
#include "rdsim/envs/manipulation/manipulation_env.hpp"
#include "rdsim/envs/classic/pendulum.hpp"
#include "rdsim/envs/reaching/reach_arm.hpp"

namespace rdsim {
namespace {

// Every key some env reads (core's and every env's option groups).
const std::vector<std::string>& declared_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> all;
    for (const EnvEntry& e : env_registry())
      for (const std::string& k : env_keys(e))
        if (std::find(all.begin(), all.end(), k) == all.end()) all.push_back(k);
    return all;
  }();
  return keys;
}

// Core's keys an env reads (the drawing ones only with cameras), through `v`.
template <class V, class C>
void describe_core(V& v, C& config, bool supports_pixels) {
  describe_env_basics(v, config);
  if (supports_pixels) describe_env_drawing(v, config);
}

// `config`'s groups in the order of `defaults`' (the env's), each taken from `config` when it has
// one of that type, else from the defaults; groups the env does not read are dropped.
std::vector<const EnvOptions*> groups_of(const EnvConfig& config, const EnvConfig& defaults) {
  std::vector<const EnvOptions*> out;
  for (const EnvOptions& d : defaults.options) {
    const EnvOptions* pick = &d;
    for (const EnvOptions& o : config.options)
      if (o.type() == d.type()) pick = &o;
    out.push_back(pick);
  }
  return out;
}

}  // namespace

const std::vector<EnvEntry>& env_registry() {
  static const std::vector<EnvEntry> entries = {
      {"cartpole", "Classic cart-pole balancing (Gym CartPole-v1 dynamics), Discrete(2)", false, cartpole_defaults,
       make_cartpole},
      {"pendulum", "Inverted pendulum swing-up (Gymnasium Pendulum-v1 dynamics), Box(1) torque", false,
       pendulum_defaults, make_pendulum},
      {"jaka_button", "JAKA Zu 7 moves its flange to a button on a table by IK moves (RobotDrlSim 4.1)", true,
       jaka_button_defaults, make_jaka_button},
      {"jaka_obstacle", "jaka_button with a column to go around; -200 for touching it (RobotDrlSim 4.2)", true,
       jaka_obstacle_defaults, make_jaka_obstacle},
      {"inmoov_tomato", "InMoov humanoid moves its right palm to a tomato on a tree by IK moves (RobotDrlSim 4.3)",
       true, inmoov_tomato_defaults, make_inmoov_tomato},
      {"reach", "Any arm (env.urdf; the repo's Jaka by default) moves its effector link to a target point by IK moves",
       true, reach_arm_defaults, make_reach_arm},
      {"reach_goal", "An arm with a gripper (the JAKA's by default) moves its effector to a goal point; goal-conditioned, Box(3)",
       true, reach_goal_defaults, make_reach_goal},
      {"push", "An arm with a closed gripper pushes a 4 cm cube to a goal on the table; goal-conditioned, Box(3)", true,
       push_defaults, make_push},
      {"pick_and_place", "An arm with a gripper picks a 4 cm cube and places it at a goal, in the air half of the time; Box(4)",
       true, pick_and_place_defaults, make_pick_and_place},
      {"stack", "An arm with a gripper stacks two 4 cm cubes at a goal on the table; goal-conditioned, Box(4)", true,
       stack_defaults, make_stack},
  };
  return entries;
}

const EnvEntry& env_entry(const std::string& name) {
  std::string known;
  std::vector<std::string> names;
  for (const auto& e : env_registry()) {
    if (e.name == name) return e;
    known += (known.empty() ? "" : ", ") + e.name;
    names.push_back(e.name);
  }
  throw Error("unknown environment \"" + one_line(name, 60) + "\"" + did_you_mean(name, names) + " (known: " + known + ")");
}

EnvConfig default_env_config(const std::string& name) {
  const EnvEntry& entry = env_entry(name);
  EnvConfig c = entry.defaults();
  c.name = entry.name;
  return c;
}

std::vector<config::FieldDoc> env_fields(const EnvEntry& entry) {
  const EnvConfig defaults = default_env_config(entry.name);
  std::vector<config::FieldDoc> rows;
  config::FieldDocs docs(rows);
  describe_core(docs, defaults, entry.supports_pixels);
  for (const EnvOptions& group : defaults.options)
    for (config::FieldDoc& row : group.document()) rows.push_back(std::move(row));
  return rows;
}

std::vector<std::string> env_keys(const EnvEntry& entry) {
  std::vector<std::string> keys;
  for (const config::FieldDoc& row : env_fields(entry)) {
    const std::string key = row.key.substr(0, row.key.find('.'));  // an object's keys: the object once
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  }
  return keys;
}

bool env_reads(const EnvEntry& entry, const std::string& key) {
  const std::vector<std::string> keys = env_keys(entry);
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

void resolve_env_paths(EnvConfig& config, const std::string& folder) {
  if (auto* arm = config.find<ArmOptions>()) resolve_arm_paths(*arm, folder);
}

namespace {

// What "randomize" needs of the rest of the env's config.
void check_randomization(ConfigReader& r, const Randomization& z, const EnvConfig& c, const std::string& name) {
  if (z.action_latency >= c.max_steps)
    r.fail("randomize.action_latency", std::to_string(z.action_latency) + " steps is not shorter than " + name +
                                           "'s episode (max_steps " + std::to_string(c.max_steps) + ")");
  if (z.noisy() && c.observation != ObservationMode::GroundTruth)
    r.fail(z.observation_noise > 0.0 ? "randomize.observation_noise" : "randomize.observation_noise_parts",
           "applies to ground-truth observations only (\"observation\": \"ground_truth\")");
  if (z.random_latency && z.action_latency == 0) r.fail("randomize.random_latency", "needs action_latency > 0");
  if (z.observe_latency && (z.queue_slots() == 0 || c.observation != ObservationMode::GroundTruth))
    r.fail("randomize.observe_latency", "needs action_latency > 0 (or latency_slots) and ground-truth observations");
  if (z.latency_slots > 0 && !z.observe_latency) r.fail("randomize.latency_slots", "has no effect without observe_latency");
  if (z.latency_slots > 0 && z.latency_slots < z.action_latency)
    r.fail("randomize.latency_slots", std::to_string(z.latency_slots) + " slots cannot hold an action_latency of " +
                                          std::to_string(z.action_latency));
  if (z.varies_view() && c.observation != ObservationMode::RawPixels)
    r.fail(z.camera_shift > 0.0  ? "randomize.camera_shift"
           : z.camera_turn > 0.0 ? "randomize.camera_turn"
           : z.camera_fov > 0.0  ? "randomize.camera_fov"
           : z.colour_noise > 0.0 ? "randomize.colour_noise"
                                  : "randomize.light_turn",
           "applies to raw-pixel observations only (\"observation\": \"raw_pixels\")");
}

}  // namespace

EnvConfig read_env_config(ConfigReader& r) {
  std::string name;
  r.read("name", name);
  if (name.empty()) r.fail("name", "expected an environment name (see `rdsim envs`)");
  const EnvEntry* entry = nullptr;
  try {
    entry = &env_entry(name);
  } catch (const Error& e) {
    r.fail("name", e.what());
  }
  // Keys another env declares but this env does not read would silently do nothing.
  const std::vector<std::string> keys = env_keys(*entry);
  const std::vector<std::string>& declared = declared_keys();
  for (const auto& key : r.keys()) {
    if (std::find(declared.begin(), declared.end(), key) != declared.end() &&
        std::find(keys.begin(), keys.end(), key) == keys.end()) {
      std::string list;
      for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
      r.fail(key, "has no effect on " + name + " (it reads: " + list + ")");
    }
  }
  const EnvConfig defaults = default_env_config(name);
  EnvConfig c = defaults;
  config::FieldReader fields(r);
  describe_core(fields, c, entry->supports_pixels);
  for (EnvOptions& group : c.options) group.read(r);
  r.finish();
  if (c.observation == ObservationMode::RawPixels && !entry->supports_pixels)
    r.fail("observation", name + " has no camera: expected \"ground_truth\"");
  // Image options only matter when something is drawn.
  const bool pixels = c.observation == ObservationMode::RawPixels, frames = c.render_mode == RenderMode::RgbArray;
  if (!pixels && c.image_width != defaults.image_width)
    r.fail("image_width", "has no effect without \"observation\": \"raw_pixels\"");
  if (!pixels && c.image_height != defaults.image_height)
    r.fail("image_height", "has no effect without \"observation\": \"raw_pixels\"");
  if (!pixels && c.image_channels != defaults.image_channels)
    r.fail("image_channels", "has no effect without \"observation\": \"raw_pixels\"");
  if (!frames && c.render_width != defaults.render_width)
    r.fail("render_width", "has no effect without \"render_mode\": \"rgb_array\"");
  if (!frames && c.render_height != defaults.render_height)
    r.fail("render_height", "has no effect without \"render_mode\": \"rgb_array\"");
  if (!pixels && !frames && c.renderer != defaults.renderer)
    r.fail("renderer", "has no effect when nothing is drawn (needs \"observation\": \"raw_pixels\" or \"render_mode\": \"rgb_array\")");
  if (const auto* group = c.find<RandomizeOptions>()) check_randomization(r, group->randomize, c, name);
  return c;
}

nlohmann::json to_json(const EnvConfig& config) {
  const EnvEntry& entry = env_entry(config.name);
  nlohmann::json out = nlohmann::json::object();
  config::FieldWriter fields(out);
  describe_core(fields, config, entry.supports_pixels);
  const EnvConfig defaults = default_env_config(config.name);
  for (const EnvOptions* group : groups_of(config, defaults)) group->write(out);
  return out;
}

Spec env_spec(const EnvConfig& config) {
  // The same env with nothing to draw (its drawing options back at their defaults).
  const EnvConfig d = default_env_config(config.name);
  EnvConfig probe = config;
  probe.observation = d.observation;
  probe.render_mode = d.render_mode;
  probe.multi_view = d.multi_view;
  probe.image_width = d.image_width;
  probe.image_height = d.image_height;
  probe.image_channels = d.image_channels;
  probe.render_width = d.render_width;
  probe.render_height = d.render_height;
  probe.renderer = d.renderer;
  if (auto* randomize = probe.find<RandomizeOptions>()) {  // nor anything to vary in a drawing
    Randomization& r = randomize->randomize;
    r.camera_shift = r.camera_turn = r.camera_fov = r.colour_noise = r.light_turn = 0.0;
  }
  Spec spec = make_env(probe)->spec();
  if (config.observation == ObservationMode::RawPixels)
    spec.observation = spec.goal.active() ? pixel_goal_space(pixel_space(config), spec.observation, spec.goal) : pixel_space(config);
  return spec;
}

void estimate_env_memory(const EnvConfig& config, int num_envs, MemoryEstimate& estimate) {
  const EnvEntry& entry = env_entry(config.name);
  // Measured resident size of one env (VmRSS before and after building it): a Bullet world with
  // its robot is a few MB; CartPole is a few numbers.
  const double physics = entry.supports_pixels ? 8e6 : 1e3;
  estimate.add("env physics (num_envs)", physics * num_envs);
  // Per drawn pixel and camera: the renderer's colour and depth buffers and its working copies,
  // the RGB image, and the observation copies VecEnv and the algorithm keep.
  constexpr double bytes_per_pixel = 32.0;
  if (config.observation == ObservationMode::RawPixels) {
    const double pixels = static_cast<double>(config.image_width) * config.image_height * (config.multi_view ? 2 : 1);
    // Float32 channels (image_channels): the larger observation in each of its three copies, and
    // the depth and id images the renderer writes.
    const ImageChannels channels(config.image_channels);
    const double floats = channels.uint8() ? 0.0 : 3.0 * (4.0 * channels.count() - 3.0) + 5.0;
    estimate.add("raw-pixel images (env.image_width x image_height x num_envs)",
                 (bytes_per_pixel + floats) * pixels * num_envs);
  }
  if (config.render_mode == RenderMode::RgbArray) {
    const double pixels = static_cast<double>(config.render_width) * config.render_height;
    estimate.add("rendered frames (env.render_width x render_height x num_envs)", bytes_per_pixel * pixels * num_envs);
  }
}

std::unique_ptr<Env> make_env(const EnvConfig& config) {
  const EnvEntry& entry = env_entry(config.name);
  // The same rules as a config file: write the values out and read them back.
  // (The config read back is the one the env gets: the same values, with every option group the
  // env reads, even when `config` was built in code without them.)
  const nlohmann::json json = to_json(config);
  ConfigReader reader(json, config.name, "env");
  const EnvConfig resolved = read_env_config(reader);
  std::unique_ptr<Env> env = entry.make(resolved);
  if (const auto* r = resolved.find<RandomizeOptions>()) return randomized(std::move(env), r->randomize);
  return env;
}

}  // namespace rdsim
