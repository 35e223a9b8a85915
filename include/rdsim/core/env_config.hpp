#pragma once
#include <string>
#include <vector>

#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/env_options.hpp"

namespace rdsim {

enum class ObservationMode { GroundTruth, RawPixels };
enum class RenderMode { None, RgbArray };

// The "env" object of a training config: the keys every env has (what the agent sees, the action
// kind, the episode length) and the drawing keys of the envs with cameras, here; each env's own
// options (the reaching tasks' IK, drive, target and workspace rules, the obstacle's column, ...)
// live with the env as option groups (core/env_options.hpp) that `options` holds. Every registered
// env publishes its defaults with real values, its groups included (default_env_config in
// envs/registry.hpp); a config is read over them, so the resolved config records the numbers an
// env really used. The initial values below are the generic ones.
struct EnvConfig {
  std::string name;
  ObservationMode observation = ObservationMode::GroundTruth;
  bool is_discrete = true;
  int max_steps = 200;
  RenderMode render_mode = RenderMode::None;
  bool multi_view = false;
  int image_width = 64;
  int image_height = 64;
  std::string image_channels = "rgb";  // image_channel_names(): what a raw-pixel observation's pixels hold
  int render_width = 320;
  int render_height = 240;
  std::string renderer = "osmesa";
  // The env's own option groups, one struct each (e.g. ReachOptions), as its defaults list them.
  std::vector<EnvOptions> options{};

  // The group of type T, or nullptr when this config has none (an env that does not read it).
  template <class T>
  T* find() {
    for (EnvOptions& o : options)
      if (T* t = o.get<T>()) return t;
    return nullptr;
  }
  template <class T>
  const T* find() const {
    for (const EnvOptions& o : options)
      if (const T* t = o.get<T>()) return t;
    return nullptr;
  }
  // The group of type T; rdsim::Error naming the env when it has none.
  template <class T>
  T& get() {
    if (T* t = find<T>()) return *t;
    throw_missing_group();
  }
  template <class T>
  const T& get() const {
    if (const T* t = find<T>()) return *t;
    throw_missing_group();
  }

private:
  [[noreturn]] void throw_missing_group() const;
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

// EnvConfig::image_channels: the images a raw-pixel observation stacks, in the order r, g, b, depth,
// segmentation (envs/pixel_view.hpp). "rgb" alone is the UInt8 image; any other is Float32.
inline const std::vector<std::string>& image_channel_names() {
  static const std::vector<std::string> names = {"rgb", "rgb_depth", "rgb_depth_segmentation", "rgb_segmentation",
                                                 "depth", "depth_segmentation", "segmentation"};
  return names;
}

// The keys every env reads.
template <class V, class C>
  requires config::Describes<C, EnvConfig>
void describe_env_basics(V& v, C& c) {
  v.field("name", c.name, "registry name (`rdsim envs`)");
  v.check(!c.name.empty(), "name", "expected an environment name (see `rdsim envs`)");
  v.choice("observation", c.observation, observation_mode_names(),
           "what the agent sees: ground-truth vectors or camera images (image_channels)");
  v.field("is_discrete", c.is_discrete, "Discrete(6) end-effector moves, else a continuous Box(3)");
  v.field("max_steps", c.max_steps, config::Range{1, 100'000'000}, "truncation limit (env steps)");
}

// The drawing keys, read by the envs with cameras (EnvEntry::supports_pixels).
template <class V, class C>
  requires config::Describes<C, EnvConfig>
void describe_env_drawing(V& v, C& c) {
  v.choice("render_mode", c.render_mode, render_mode_names(),
           "the paper's `renders`: rgb_array makes Env::render draw frames for people");
  v.field("multi_view", c.multi_view, "raw pixels from a second camera too (6 channels)");
  v.field("image_width", c.image_width, config::Range{8, 4096}, "raw-pixel observation width");
  v.field("image_height", c.image_height, config::Range{8, 4096}, "raw-pixel observation height");
  v.choice("image_channels", c.image_channels, image_channel_names(),
           "what each pixel of a raw-pixel observation holds: rgb = UInt8 colour; the others Float32 channels in "
           "this order, per camera: r, g, b in [0, 1], depth in metres along the camera's axis (the far plane where "
           "nothing is), segmentation id (0 background, then the robot's links, then the other bodies: docs: Environments)");
  v.field("render_width", c.render_width, config::Range{8, 4096}, "width of Env::render frames (render_mode rgb_array)");
  v.field("render_height", c.render_height, config::Range{8, 4096}, "height of those frames");
  v.choice("renderer", c.renderer, {"osmesa", "egl", "auto"},
           "renderer backend: osmesa (CPU), egl (GPU through EGL when built), auto (egl when it works)");
  v.check(!c.multi_view || c.observation == ObservationMode::RawPixels, "multi_view",
          "has no effect without \"observation\": \"raw_pixels\" (it adds a second camera to the images)");
}

// Both: every key core declares (the option groups describe their own).
template <class V, class C>
  requires config::Describes<C, EnvConfig>
void describe(V& v, C& c) {
  describe_env_basics(v, c);
  describe_env_drawing(v, c);
}

const char* to_string(ObservationMode mode);
const char* to_string(RenderMode mode);

}  // namespace rdsim
