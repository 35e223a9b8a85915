#pragma once
#include <string>

#include "rdsim/core/config_fields.hpp"

namespace rdsim {

enum class ObservationMode { GroundTruth, RawPixels };
enum class RenderMode { None, RgbArray };

// Options shared by all environments (the paper's Table 1 parameters and a few more): the "env"
// object of a training config. Every registered env publishes its defaults with real values
// (default_env_config in envs/registry.hpp); a config is read over them, so the resolved config
// records the numbers an env really used. The initial values below are the generic ones.
struct EnvConfig {
  std::string name;
  ObservationMode observation = ObservationMode::GroundTruth;
  bool is_discrete = true;
  RenderMode render_mode = RenderMode::None;
  bool multi_view = false;
  bool random_target = false;
  double max_distance = 0.7;        // m
  std::string urdf_root{};          // empty = the repo's assets/ (asset_root)
  int max_steps = 200;
  double action_step = 0.015;       // m
  double success_threshold = 0.025; // m
  int action_repeat = 1;
  int image_width = 64;
  int image_height = 64;
  int render_width = 320;
  int render_height = 240;
  std::string renderer = "osmesa";
};

inline const config::Names<ObservationMode>& observation_mode_names() {
  static const config::Names<ObservationMode> names = {{"ground_truth", ObservationMode::GroundTruth},
                                                       {"raw_pixels", ObservationMode::RawPixels}};
  return names;
}
inline const config::Names<RenderMode>& render_mode_names() {
  static const config::Names<RenderMode> names = {{"none", RenderMode::None}, {"rgb_array", RenderMode::RgbArray}};
  return names;
}

template <class V, class C>
  requires config::Describes<C, EnvConfig>
void describe(V& v, C& c) {
  v.field("name", c.name, "registry name (`rdsim envs`)");
  v.check(!c.name.empty(), "name", "expected an environment name (see `rdsim envs`)");
  v.choice("observation", c.observation, observation_mode_names(),
           "what the agent sees: ground-truth vectors or UInt8 camera images");
  v.field("is_discrete", c.is_discrete, "Discrete(6) end-effector moves, else a continuous Box(3)");
  v.choice("render_mode", c.render_mode, render_mode_names(),
           "the paper's `renders`: rgb_array makes Env::render draw frames for people");
  v.field("multi_view", c.multi_view, "raw pixels from a second camera too (6 channels)");
  v.field("random_target", c.random_target, "target drawn at each reset");
  v.field("max_distance", c.max_distance, config::Range{1e-3, 100.0},
          "m; farther than this from the target ends the episode");
  v.field("urdf_root", c.urdf_root, "folder holding the URDF assets; empty = the repo's assets/");
  v.field("max_steps", c.max_steps, config::Range{1, 100'000'000}, "truncation limit (env steps)");
  v.field("action_step", c.action_step, config::Range{1e-4, 0.2}, "m per discrete move / largest continuous move");
  v.field("success_threshold", c.success_threshold, config::Range{1e-4, 10.0}, "m; closer than this to the target is success");
  v.field("action_repeat", c.action_repeat, config::Range{1, 1000}, "physics steps (1/240 s) per env step");
  v.field("image_width", c.image_width, config::Range{8, 4096}, "raw-pixel observation width");
  v.field("image_height", c.image_height, config::Range{8, 4096}, "raw-pixel observation height");
  v.field("render_width", c.render_width, config::Range{8, 4096}, "width of Env::render frames (render_mode rgb_array)");
  v.field("render_height", c.render_height, config::Range{8, 4096}, "height of those frames");
  v.choice("renderer", c.renderer, {"osmesa", "egl", "auto"},
           "renderer backend: osmesa (CPU), egl (GPU through EGL when built), auto (egl when it works)");
  v.check(!c.multi_view || c.observation == ObservationMode::RawPixels, "multi_view",
          "has no effect without \"observation\": \"raw_pixels\" (it adds a second camera to the images)");
}

const char* to_string(ObservationMode mode);
const char* to_string(RenderMode mode);

// The folder holding rdsim's assets: `urdf_root` when set, else $RDSIM_ROOT/assets,
// else the source tree's assets/ (known at build time).
std::string asset_root(const EnvConfig& config);

}  // namespace rdsim
