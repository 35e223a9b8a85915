#include "rdsim/env_config.hpp"

#include <cstdlib>
#include <nlohmann/json.hpp>

namespace rdsim {

const char* to_string(ObservationMode mode) {
  return mode == ObservationMode::RawPixels ? "raw_pixels" : "ground_truth";
}

const char* to_string(RenderMode mode) { return mode == RenderMode::RgbArray ? "rgb_array" : "none"; }

EnvConfig read_env_config(ConfigReader& r) {
  EnvConfig c;
  r.read("name", c.name);
  if (c.name.empty()) r.fail("name", "expected an environment name (see `rdsim envs`)");
  std::string obs = to_string(c.observation);
  r.read_choice("observation", obs, {"ground_truth", "raw_pixels"});
  c.observation = obs == "raw_pixels" ? ObservationMode::RawPixels : ObservationMode::GroundTruth;
  std::string render = to_string(c.render_mode);
  r.read_choice("render_mode", render, {"none", "rgb_array"});
  c.render_mode = render == "rgb_array" ? RenderMode::RgbArray : RenderMode::None;
  r.read("is_discrete", c.is_discrete);
  r.read("multi_view", c.multi_view);
  r.read("random_target", c.random_target);
  r.read("max_distance", c.max_distance, 0.0, 100.0);
  r.read("urdf_root", c.urdf_root);
  r.read("max_steps", c.max_steps, 0, 100000000);
  r.read("action_step", c.action_step, 0.0, 1.0);
  r.read("success_threshold", c.success_threshold, 0.0, 10.0);
  r.read("action_repeat", c.action_repeat, 1, 1000);
  r.read("image_width", c.image_width, 8, 4096);
  r.read("image_height", c.image_height, 8, 4096);
  r.read("render_width", c.render_width, 8, 4096);
  r.read("render_height", c.render_height, 8, 4096);
  r.read_choice("renderer", c.renderer, {"osmesa", "egl", "auto"});
  r.finish();
  return c;
}

nlohmann::json to_json(const EnvConfig& c) {
  return {{"name", c.name},
          {"observation", to_string(c.observation)},
          {"render_mode", to_string(c.render_mode)},
          {"is_discrete", c.is_discrete},
          {"multi_view", c.multi_view},
          {"random_target", c.random_target},
          {"max_distance", c.max_distance},
          {"urdf_root", c.urdf_root},
          {"max_steps", c.max_steps},
          {"action_step", c.action_step},
          {"success_threshold", c.success_threshold},
          {"action_repeat", c.action_repeat},
          {"image_width", c.image_width},
          {"image_height", c.image_height},
          {"render_width", c.render_width},
          {"render_height", c.render_height},
          {"renderer", c.renderer}};
}

std::string asset_root(const EnvConfig& config) {
  if (!config.urdf_root.empty()) return config.urdf_root;
  if (const char* root = std::getenv("RDSIM_ROOT"); root && *root) return std::string(root) + "/assets";
  return std::string(RDSIM_SOURCE_DIR) + "/assets";
}

}  // namespace rdsim
