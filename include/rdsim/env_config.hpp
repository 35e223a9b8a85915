#pragma once
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "rdsim/config_reader.hpp"

namespace rdsim {

enum class ObservationMode { GroundTruth, RawPixels };
enum class RenderMode { None, RgbArray };

// Options shared by all environments (the paper's Table 1 parameters and a few more).
// A value of 0 for the task numbers means "the environment's documented default".
struct EnvConfig {
  std::string name;                                       // registry name, e.g. "jaka_button"
  ObservationMode observation = ObservationMode::GroundTruth;
  bool is_discrete = true;          // Discrete(6) end-effector moves, else a continuous box
  RenderMode render_mode = RenderMode::None;
  bool multi_view = false;          // raw pixels from a second camera too
  bool random_target = false;       // target position randomised at each reset
  double max_distance = 0.0;        // m; farther than this from the target ends the episode
  std::string urdf_root;            // asset folder; empty = the repo's assets/
  int max_steps = 0;                // truncation limit
  double action_step = 0.0;         // m per discrete move / largest continuous move
  double success_threshold = 0.0;   // m; closer than this to the target is success
  int action_repeat = 1;            // physics steps per env step
  int image_width = 64;             // raw-pixel observation size
  int image_height = 64;
  int render_width = 320;           // Env::render frames (render_mode rgb_array)
  int render_height = 240;
  std::string renderer = "osmesa";  // renderer backend: "osmesa" | "egl" | "auto" (egl if it works)
};

// Reads the "env" object of a config (unknown keys rejected).
EnvConfig read_env_config(ConfigReader& reader);
nlohmann::json to_json(const EnvConfig& config);

const char* to_string(ObservationMode mode);
const char* to_string(RenderMode mode);

// The folder holding rdsim's assets: `urdf_root` when set, else $RDSIM_ROOT/assets,
// else the source tree's assets/ (known at build time).
std::string asset_root(const EnvConfig& config);

}  // namespace rdsim
