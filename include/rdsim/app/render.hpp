#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rdsim {

// `rdsim render`: the image an env's agent sees after reset (raw-pixel observation) as a PNG.
struct RenderOptions {
  std::string env;                 // registry name (its defaults); or
  std::string config_path;         // a training config: its "env" object (a user's robot, its options)
  std::string out_path;            // PNG file to write
  int view = 1;                    // 1 = main camera, 2 = the second (multi_view) camera
  int width = 64;                  // image size (env.image_width / image_height)
  int height = 64;
  std::uint64_t seed = 0;          // reset seed
  bool random_target = false;      // env.random_target, so the seed moves the target (a config's own value otherwise)
};
int render_command(const RenderOptions& options);

}  // namespace rdsim
